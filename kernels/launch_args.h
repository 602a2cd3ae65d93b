// Work-group counts for indirect dispatch (the Vulkan backend's vkCmdDispatchIndirect). A queue's item count
// lives in a device counter that the previous stage wrote, so the dispatch is sized on the device: no host round
// trip, and no groups launched that would find no work at the deep, sparse bounces. The grid loop (RT_GRID_LOOP)
// still covers any count, so capping at the backend's fixed grid keeps the launch shape of docs/fairness.md.
#ifndef RT_LAUNCH_ARGS_H
#define RT_LAUNCH_ARGS_H

#include "stages.h"

// Which count sizes a stage's launch.
#define RT_LAUNCH_PIXELS 0u    // generate, resolve
#define RT_LAUNCH_RAYS 1u      // intersect, miss and shade of one depth
#define RT_LAUNCH_SHADOWS 2u   // shadow of one depth
#define RT_LAUNCH_SLOTS (1u + 2u * (RT_MAX_DEPTH + 1u))

// Slot of a launch in the argument array (one uint4 each: groups x, y, z, unused).
RT_FUNC uint rt_launch_slot(uint queue, uint depth) {
    return queue == RT_LAUNCH_PIXELS ? 0u : 1u + (queue - 1u) * (RT_MAX_DEPTH + 1u) + depth;
}

RT_FUNC uint rt_launch_items(KernelGlobals kg, uint queue, uint depth) {
    if (queue == RT_LAUNCH_PIXELS) return rt_pixel_count(kg);
    if (queue == RT_LAUNCH_RAYS) return rt_ray_count(kg, depth);
    return rt_shadow_count(kg, depth);
}

// Enough groups for every item, at most `max_groups` (the grid loop strides over the rest).
RT_FUNC uint rt_launch_groups(uint items, uint group_size, uint max_groups) {
    return rt_min_u((items + group_size - 1u) / group_size, max_groups);
}

#endif
