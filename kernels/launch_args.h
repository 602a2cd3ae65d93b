// Work-group counts for indirect dispatch (the Vulkan backend's vkCmdDispatchIndirect). A queue's item count
// lives in a device counter that the previous stage wrote, so the dispatch is sized on the device: no host round
// trip, and no groups launched that would find no work at the deep, sparse bounces. The grid loop (RT_GRID_LOOP)
// still covers any count, so capping at the backend's fixed grid keeps the launch shape of docs/fairness.md.
#ifndef RT_LAUNCH_ARGS_H
#define RT_LAUNCH_ARGS_H

#include "stages.h"

// Which count sizes a stage's launch, and its slot in the argument array (one uint4 each: groups x, y, z, unused):
// slot 0 the pixels (generate, resolve), then the rays of each depth (intersect, miss, shade), then the shadow
// rays of each depth (shadow).
#define RT_LAUNCH_PIXELS 0u
#define RT_LAUNCH_RAYS 1u
#define RT_LAUNCH_SHADOWS 2u
#define RT_LAUNCH_SLOTS (1u + 2u * (RT_MAX_DEPTH + 1u))

RT_FUNC uint rt_launch_slot(uint queue, uint depth) {
    return queue == RT_LAUNCH_PIXELS ? 0u : 1u + (queue - 1u) * (RT_MAX_DEPTH + 1u) + depth;
}

// Items of the launch in `slot`, from the counters as they are now.
RT_FUNC uint rt_launch_items(KernelGlobals kg, uint slot) {
    if (slot == 0u) return rt_pixel_count(kg);
    if (slot <= RT_MAX_DEPTH + 1u) return rt_ray_count(kg, slot - 1u);
    return rt_shadow_count(kg, slot - 1u - (RT_MAX_DEPTH + 1u));
}

// Enough groups for every item, at most `max_groups` (the grid loop strides over the rest).
RT_FUNC uint rt_launch_groups(uint items, uint group_size, uint max_groups) {
    return rt_min_u((items + group_size - 1u) / group_size, max_groups);
}

#endif
