// Vulkan entry point of the 'generate' stage (kernels/stages.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

void main() { rt_kernel_generate(0, pc.depth); }
