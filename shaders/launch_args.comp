// Vulkan only: refreshes the indirect-dispatch arguments when no generate or shadow stage has (ray queries, whose
// counts the host writes). One work-group (shaders/launch_args.glsl).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "launch_args.glsl"

void main() { rt_vk_fill_launch_args(); }
