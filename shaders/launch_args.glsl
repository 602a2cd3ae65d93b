// Vulkan only: writes every launch's indirect-dispatch arguments from the device-side queue counters
// (kernels/launch_args.h), invocation i slot i. launch_args.comp runs it alone; generate.comp and shadow.comp run it
// in passing, since the counts they see are final for the launches after them (generate: the primary rays the host
// queued; shadow: the next depth's rays, which shade appended).
#include "launch_args.h"

layout(std430, set = 0, binding = RT_VK_BINDING_LAUNCH_ARGS) writeonly buffer launch_args_block { uvec4 launch_args[]; };

void rt_vk_fill_launch_args() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= RT_LAUNCH_SLOTS) return;
    launch_args[slot] = uvec4(rt_launch_groups(rt_launch_items(0, slot), gl_WorkGroupSize.x, pc.groups), 1u, 1u, 0u);
}
