// Vulkan entry point of the 'shade' stage (kernels/stages.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

void main() { rt_kernel_shade(0, pc.depth); }
