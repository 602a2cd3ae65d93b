// Vulkan entry point of the 'resolve' stage (kernels/stages.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

void main() { rt_kernel_resolve(0, pc.depth); }
