// Vulkan only: sizes the next indirect dispatch from the device-side queue counters (kernels/launch_args.h).
// One invocation; the push constant's depth holds queue << 8 | depth.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "launch_args.h"

layout(std430, set = 0, binding = RT_VK_BINDING_LAUNCH_ARGS) writeonly buffer launch_args_block { uvec4 launch_args[]; };

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    uint queue = pc.depth >> 8u;
    uint depth = pc.depth & 0xffu;
    uint groups = rt_launch_groups(rt_launch_items(0, queue, depth), gl_WorkGroupSize.x, pc.groups);
    launch_args[rt_launch_slot(queue, depth)] = uvec4(groups, 1u, 1u, 0u);
}
