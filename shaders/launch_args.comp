// Vulkan only: sizes the next indirect dispatches from the device-side queue counters (kernels/launch_args.h).
// One work-group; invocation i fills slot i, so one dispatch refreshes every launch's arguments at once.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "launch_args.h"

layout(std430, set = 0, binding = RT_VK_BINDING_LAUNCH_ARGS) writeonly buffer launch_args_block { uvec4 launch_args[]; };

void main() {
    uint slot = gl_LocalInvocationID.x;
    if (slot >= RT_LAUNCH_SLOTS) return;
    uint groups = rt_launch_groups(rt_launch_items(0, slot), gl_WorkGroupSize.x, pc.groups);
    launch_args[slot] = uvec4(groups, 1u, 1u, 0u);
}

