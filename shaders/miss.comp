// Vulkan entry point of the 'miss' stage (kernels/stages.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

void main() { rt_kernel_miss(0, pc.depth); }
