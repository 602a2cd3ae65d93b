// Vulkan entry point of the 'shadow' stage (kernels/stages.h); also sizes the launches after it
// (shaders/launch_args.glsl).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "launch_args.glsl"

void main() {
    rt_vk_fill_launch_args();
    rt_kernel_shadow(0, pc.depth);
}
