// The wavefront stages (architecture.md, "The wavefront frame"; thesis 6.4.2 improved). Each rt_stage_* handles
// one item; each rt_kernel_* is the whole launch (a grid loop over the item count, which lives on the device), so
// a backend's entry point is one line. Queues: rays of depth d live in half (d & 1) of `rays`; their hits in
// `hits`; shadow rays of depth d in `shadow_rays`; counts in `counters` (kernels/types.h).
#ifndef RT_STAGES_H
#define RT_STAGES_H

#include "accumulate.h"
#include "display.h"
#include "environment.h"
#include "shade.h"
#include "traverse.h"

// The arrays a stage streams with RT_FETCH_ONCE / RT_STORE_ONCE, for a compat layer that needs a function for each
// (compat/opencl.h on NVIDIA's platform).
#if defined(RT_ONCE_ACCESS)
RT_ONCE_ACCESS(Ray, rays)
RT_ONCE_ACCESS(Hit, hits)
RT_ONCE_ACCESS(ShadowRay, shadow_rays)
#endif

// The traversal stages' loop over n items. Where the compat layer has RT_FIRST_ITEM (the GPUs' warps and
// subgroups), each warp takes its next items from counter `slot` (zeroed with the frame's counters) with one atomic
// add whenever it is done with its last, so no warp idles while others still trace a fixed share: with the grid
// loop, a block's warps that had drawn quick rays waited for its slowest, and the intersect launch of the bunny's
// primary rays kept 33% of an SM's warp slots busy where 50% fit (docs/kernels.md, "Taking rays"). Elsewhere (the
// cpu backends, OpenCL without NVIDIA's warp votes, Vulkan on a CPU device): the grid loop.
#if defined(RT_FIRST_ITEM)
#define RT_WORK_LOOP(kg, i, n, slot) \
    for (uint rt_n_ = (n), i = RT_FIRST_ITEM(kg, slot); i < rt_n_; i = RT_NEXT_ITEM(kg, slot, i))
#else
#define RT_WORK_LOOP(kg, i, n, slot) RT_GRID_LOOP(i, n)
#endif

RT_FUNC uint rt_queue_base(FrameParams frame, uint depth) { return (depth & 1u) * frame.ray_capacity; }

RT_FUNC uint rt_ray_count(KernelGlobals kg, uint depth) {
    return rt_min_u(RT_FETCH(kg, counters, RT_COUNTER_RAYS + depth), RT_FETCH(kg, frame, 0u).ray_capacity);
}

RT_FUNC uint rt_shadow_count(KernelGlobals kg, uint depth) {
    return rt_min_u(RT_FETCH(kg, counters, RT_COUNTER_SHADOWS + depth), RT_FETCH(kg, frame, 0u).shadow_capacity);
}

RT_FUNC uint rt_pixel_count(KernelGlobals kg) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    return frame.tile_width * frame.tile_height;
}

// Primary rays through pixel centres of a pinhole camera (thesis 6.3: "rays share the camera position").
// `index` counts the pixels of the frame's tile; the ray carries it, so accumulation and the image are per tile.
RT_FUNC Ray rt_primary_ray(FrameParams frame, uint index) {
    uint x = frame.tile_x + index % frame.tile_width;
    uint y = frame.tile_y + index / frame.tile_width;
    float tan_half = frame.tan_half_fov;
    float aspect = frame.aspect;
    float px = (2.0f * (rt_float(x) + 0.5f) / rt_float(frame.width) - 1.0f) * tan_half * aspect;
    float py = (1.0f - 2.0f * (rt_float(y) + 0.5f) / rt_float(frame.height)) * tan_half;
    float3 dir =
        normalize(rt_xyz(frame.camera_forward) + rt_xyz(frame.camera_right) * px + rt_xyz(frame.camera_up) * py);
    return rt_make_ray(rt_xyz(frame.camera_position), dir, rt_splat3(1.0f), index, RT_CHANNEL_ALL, 0u);
}

RT_FUNC void rt_stage_generate(KernelGlobals kg, uint index) {
    RT_STORE(kg, rays, index, rt_primary_ray(RT_FETCH(kg, frame, 0u), index));
}

// The closest hit (intersect) or any hit (occlude, ray queries with RT_FLAG_ANY_HIT) of every queued ray. Two
// stages, not one reading the flag: each kernel is compiled for one walk, so the frame's closest-hit walk carries
// none of the any-hit walk's code (docs/kernels.md, "Any-hit walks").
RT_FUNC void rt_stage_trace(KernelGlobals kg, uint index, uint depth, bool any_hit, bool mesh) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    Ray ray = RT_FETCH_ONCE(kg, rays, rt_queue_base(frame, depth) + index);
    Hit hit = mesh
                  ? rt_trace_mesh(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), ray.origin.w, ray.direction.w, any_hit)
                  : rt_trace(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), ray.origin.w, ray.direction.w, any_hit);
    RT_STORE_ONCE(kg, hits, index, hit);
}

// Rays that left the scene see the environment (the seed's "Cube Map" kernel).
RT_FUNC void rt_stage_miss(KernelGlobals kg, uint index, uint depth) {
    Hit hit = RT_FETCH(kg, hits, index);
    if (hit.tuv.x < RT_INFINITY) return;
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    Ray ray = RT_FETCH(kg, rays, rt_queue_base(frame, depth) + index);
    rt_accumulate(kg, ray.pixel, rt_xyz(ray.weight) * rt_environment(kg, rt_xyz(ray.direction)));
}

// Takes n consecutive slots of a queue for one item and returns the first. RT_QUEUE_RESERVE sums the n of the
// items running together (a warp, a subgroup) and takes all of their slots with one atomic add; taking one slot
// per ray, the shade stage's warps spent a third of their time waiting for the counters (docs/kernels.md, "Queue
// slots"). Slots past the capacity are dropped and counted (reported, and asserted zero in the tests).
RT_FUNC uint rt_queue_reserve(KernelGlobals kg, uint counter, uint n, uint capacity) {
    uint first = RT_QUEUE_RESERVE(kg, counters, counter, n);
    if (n > 0u && first + n > capacity) {
        uint kept = first < capacity ? capacity - first : 0u;
        RT_ATOMIC_ADD(kg, counters, RT_COUNTER_DROPPED, n - kept);
    }
    return first;
}

// The seed's "Renderer" kernel: the local colour goes to the pixel, shadow rays and secondary rays to queues. The
// shadow rays are counted before they are stored, so that both queues' slots are taken at once: the two atomics
// are in flight together instead of one after the other for every ray. A group's (warp's, subgroup's) shadow rays
// go to the queue light by light: its rays towards light 0, then those towards light 1, so that the shadow stage's
// neighbours head for one light, not for each light in turn (docs/kernels.md, "Shadow and child rays in the
// queue").
RT_FUNC void rt_stage_shade(KernelGlobals kg, uint index, uint depth) {
    Hit hit = RT_FETCH(kg, hits, index);
    if (!(hit.tuv.x < RT_INFINITY)) return;
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    Ray ray = RT_FETCH(kg, rays, rt_queue_base(frame, depth) + index);
    Ray children[RT_MAX_CHILDREN];
    ShadeResult shade = rt_shade(kg, ray, hit, children);
    rt_accumulate(kg, ray.pixel, rt_xyz(shade.emitted));
    uint shadow_count = 0u;
    for (uint l = 0u; l < frame.light_count; ++l)
        if (rt_shadow_ray(kg, shade.lit, l, ray.pixel).contribution.w != 0.0f) shadow_count += 1u;
    uint shadow_slot = RT_QUEUE_RESERVE_GROUP(kg, counters, RT_COUNTER_SHADOWS + depth, shadow_count);
    uint ray_slot = rt_queue_reserve(kg, RT_COUNTER_RAYS + depth + 1u, shade.child_count, frame.ray_capacity);
    uint dropped = 0u;
    for (uint l = 0u; l < frame.light_count; ++l) {
        ShadowRay sr = rt_shadow_ray(kg, shade.lit, l, ray.pixel);
        bool lit = sr.contribution.w != 0.0f;
        uint slot = shadow_slot + RT_GROUP_COUNT_BELOW(lit);
        shadow_slot += RT_GROUP_COUNT(lit);
        if (!lit) continue;
        if (slot < frame.shadow_capacity)
            RT_STORE(kg, shadow_rays, slot, sr);
        else
            dropped += 1u;
    }
    if (dropped > 0u) RT_ATOMIC_ADD(kg, counters, RT_COUNTER_DROPPED, dropped);
    // A loop of fixed length over the children: NVIDIA's Vulkan compiler gives the stage much less work with one
    // than with a loop over the count (docs/kernels.md, "The shade stage's copy").
    uint next_base = rt_queue_base(frame, depth + 1u);
    for (uint c = 0u; c < RT_MAX_CHILDREN; ++c)
        if (c < shade.child_count && ray_slot + c < frame.ray_capacity)
            RT_STORE(kg, rays, next_base + ray_slot + c, children[c]);
}

#define RT_SHADOW_LAYERS 8u  // cut-out or blended surfaces a shadow ray looks through before it counts as blocked

// Whether some material is cut out or blended (RT_FLAG_ALPHA_SHADOWS): then the shadow_layers stage takes the
// shadow rays instead of the shadow stage. Two stages, so that the one any-hit query of every other scene compiles
// as it did before alpha shadows (a kernel holding both paths takes the registers of the larger one).
RT_FUNC bool rt_alpha_shadows(KernelGlobals kg) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);  // whole: see rt_trace
    return (frame.flags & RT_FLAG_ALPHA_SHADOWS) != 0u;
}

// All of a shadow ray's contribution reaches its point unless something lies between (one any-hit query).
RT_FUNC float3 rt_light_unblocked(KernelGlobals kg, ShadowRay sr) {
    Hit hit = rt_trace(kg, rt_xyz(sr.origin), rt_xyz(sr.direction), 0.0f, sr.direction.w, true);
    return hit.tuv.x < RT_INFINITY ? make_float3(0.0f, 0.0f, 0.0f) : rt_xyz(sr.contribution);
}

// Where some material is cut out or blended, a shadow ray takes the surfaces between in turn, nearest first, and
// keeps what each one's coverage leaves (MASK: all where cut out, none elsewhere; BLEND: 1 - alpha), as the shade
// stage passes camera and secondary rays through them; after RT_SHADOW_LAYERS surfaces it counts as blocked.
// Refractive surfaces block, as in the seed (Whitted shadows do not refract).
RT_FUNC float3 rt_light_through_layers(KernelGlobals kg, ShadowRay sr) {
    float3 origin = rt_xyz(sr.origin);
    float3 direction = rt_xyz(sr.direction);
    float distance = sr.direction.w;
    float3 reaching = rt_xyz(sr.contribution);
    for (uint layer = 0u; layer < RT_SHADOW_LAYERS; ++layer) {
        Hit hit = rt_trace(kg, origin, direction, 0.0f, distance, false);
        if (!(hit.tuv.x < RT_INFINITY)) return reaching;
        Surface s = rt_surface_at(kg, direction, hit, false);
        Material m = RT_FETCH(kg, materials, s.material);
        reaching = reaching * (1.0f - rt_coverage(kg, m, s.vertex_color, s.uv));
        if (!(rt_max3(reaching) > 0.0f)) break;
        // On from the surface's far side, the rest of the way (a directional light's stays infinite).
        float3 next = rt_offset_ray_origin(rt_xyz(s.position), -rt_xyz(s.geometric));
        distance = distance - dot(next - origin, direction);
        origin = next;
    }
    return make_float3(0.0f, 0.0f, 0.0f);
}

// What of a shadow ray's contribution reaches its point, by the rule of the scene (cpu-ref; the GPU frame splits
// the two rules into the shadow and shadow_layers stages).
RT_FUNC float3 rt_light_reaching(KernelGlobals kg, ShadowRay sr) {
    return rt_alpha_shadows(kg) ? rt_light_through_layers(kg, sr) : rt_light_unblocked(kg, sr);
}

// A light reaches the point unless something lies between.
RT_FUNC void rt_stage_shadow(KernelGlobals kg, uint index, uint depth) {
    ShadowRay sr = RT_FETCH_ONCE(kg, shadow_rays, index);
    float3 reaching = rt_light_unblocked(kg, sr);
    if (rt_max3(reaching) > 0.0f) rt_accumulate(kg, sr.pixel, reaching);
}

// What a light leaves through the cut-out and blended surfaces between it and the point.
RT_FUNC void rt_stage_shadow_layers(KernelGlobals kg, uint index, uint depth) {
    ShadowRay sr = RT_FETCH_ONCE(kg, shadow_rays, index);
    float3 reaching = rt_light_through_layers(kg, sr);
    if (rt_max3(reaching) > 0.0f) rt_accumulate(kg, sr.pixel, reaching);
}

#if defined(RT_WIDE_TRAVERSAL)
// The cpu backends' traversal stages on a wide scene: items [begin, end) of the ray queue of `depth` (intersect,
// occlude) or of its shadow rays (shadow), two walks at a time: each walk's steps wait on their node's or leaf's
// loads, and the other walk's step is independent work for the core meanwhile; a walk that ends hands its result on
// and starts the next item at once (docs/kernels.md, "Two walks at a time"). Each item's result is what
// rt_stage_trace or rt_stage_shadow gives it: the walks are rt_trace_wide's, a step at a time.
RT_STRUCT_BEGIN(WalkItem)
    float4 origin;     // w = tmin
    float4 direction;  // w = tmax
RT_STRUCT_END(WalkItem)

RT_FUNC WalkItem rt_walk_item(KernelGlobals kg, uint base, uint index, bool shadows) {
    WalkItem item;
    if (shadows) {
        ShadowRay sr = RT_FETCH(kg, shadow_rays, index);
        item.origin = rt_float4(rt_xyz(sr.origin), 0.0f);
        item.direction = sr.direction;
    } else {
        Ray ray = RT_FETCH(kg, rays, base + index);
        item.origin = ray.origin;
        item.direction = ray.direction;
    }
    return item;
}

RT_FUNC WideWalk rt_walk_start(KernelGlobals kg, WalkItem item, bool one_instance, bool flat) {
    return rt_wide_start(kg, rt_xyz(item.origin), rt_xyz(item.direction), item.origin.w, item.direction.w,
                         one_instance && !flat);
}

// A finished walk: the hit into the hit queue, or a shadow ray's light onto its pixel unless something blocked it.
RT_FUNC void rt_walk_done(KernelGlobals kg, uint index, bool shadows, Hit hit) {
    if (!shadows) {
        RT_STORE(kg, hits, index, hit);
    } else if (!(hit.tuv.x < RT_INFINITY)) {
        ShadowRay sr = RT_FETCH(kg, shadow_rays, index);
        if (rt_max3(rt_xyz(sr.contribution)) > 0.0f) rt_accumulate(kg, sr.pixel, rt_xyz(sr.contribution));
    }
}

// One of rt_walk_range's two walks: the item it walks and where the walk is (its best hit and rays, WideWalk, and
// its stack are the caller's).
RT_STRUCT_BEGIN(WalkSlot)
    WalkItem item;
    WidePosition at;
    uint index;  // the item's
    uint next;   // the range's next item to start, handed from one walk to the other
    uint end;    // the range's end
    uint base;   // the ray queue's first slot at this depth
RT_STRUCT_END(WalkSlot)

RT_FUNC WalkSlot rt_walk_slot(KernelGlobals kg, WalkSlot s, RT_OUT_ARRAY WideWalk* walk, uint index, bool shadows,
                              bool one_instance, bool flat) {
    s.index = index;
    s.item = rt_walk_item(kg, s.base, index, shadows);
    walk[0] = rt_walk_start(kg, s.item, one_instance, flat);
    s.at = rt_wide_start_position(kg, one_instance, flat);
    return s;
}

// A step of the slot's walk; a walk that ends hands on its result and starts the range's next item.
RT_FUNC_INLINE WalkSlot rt_walk_advance(KernelGlobals kg, WalkSlot s, RT_OUT_ARRAY WideWalk* walk,
                                        RT_OUT_ARRAY uint2* stack, bool any_hit, bool shadows, bool one_instance,
                                        bool flat) {
    if (s.at.going == 0u) return s;
    s.at = rt_wide_step(kg, s.at, walk, stack, s.item.origin.w, s.item.direction.w, any_hit);
    if (s.at.going != 0u) return s;
    rt_walk_done(kg, s.index, shadows, rt_wide_result(walk[0]));
    if (s.next >= s.end) return s;
    s.next += 1u;
    return rt_walk_slot(kg, s, walk, s.next - 1u, shadows, one_instance, flat);
}

RT_FUNC void rt_walk_range(KernelGlobals kg, uint begin, uint end, uint depth, bool any_hit, bool shadows) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    bool one_instance = (frame.flags & RT_FLAG_ONE_INSTANCE) != 0u;
    bool flat = (frame.flags & RT_FLAG_FLAT_INSTANCES) != 0u;
    uint2 stack_a[RT_BVH_WIDE_STACK_SIZE];
    uint2 stack_b[RT_BVH_WIDE_STACK_SIZE];
    WideWalk walk_a;
    WideWalk walk_b;
    WalkSlot a;
    a.base = rt_queue_base(frame, depth);
    a.end = end;
    a.next = begin + 2u;
    WalkSlot b = a;
    // Walk a takes item begin and walk b the next one; with a single item, b starts on it too but never steps.
    a = rt_walk_slot(kg, a, &walk_a, begin, shadows, one_instance, flat);
    b = rt_walk_slot(kg, b, &walk_b, rt_min_u(begin + 1u, end - 1u), shadows, one_instance, flat);
    if (b.index == a.index) b.at.going = 0u;
    while ((a.at.going | b.at.going) != 0u) {
        a = rt_walk_advance(kg, a, &walk_a, stack_a, any_hit, shadows, one_instance, flat);
        b.next = a.next;
        b = rt_walk_advance(kg, b, &walk_b, stack_b, any_hit, shadows, one_instance, flat);
        a.next = b.next;
    }
}
#endif

// Fixed point to linear radiance and 8-bit sRGB. The pixel's light times the exposure, through the tone map if the
// frame has one, is the frame's radiance (what .exr, .hdr and 16-bit PNG files are written from: linear, and
// unclamped without a tone map) and, in sRGB, its image: every output shows the same picture.
RT_FUNC void rt_stage_resolve(KernelGlobals kg, uint index) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    float3 c =
        rt_display_color(rt_accumulated(kg, index) * frame.exposure, (frame.flags & RT_FLAG_TONE_MAP_NEUTRAL) != 0u);
    RT_STORE(kg, radiance, index, rt_float4(c, 1.0f));
    uint r = rt_uint(rt_linear_to_srgb(c.x) * 255.0f + 0.5f);
    uint g = rt_uint(rt_linear_to_srgb(c.y) * 255.0f + 0.5f);
    uint b = rt_uint(rt_linear_to_srgb(c.z) * 255.0f + 0.5f);
    RT_STORE(kg, image, index, r | (g << 8u) | (b << 16u) | (255u << 24u));
}

// Whole launches: what a backend's one-line entry point calls.
RT_FUNC void rt_kernel_generate(KernelGlobals kg, uint depth) {
    RT_GRID_LOOP(i, rt_pixel_count(kg)) { rt_stage_generate(kg, i); }
}
RT_FUNC bool rt_mesh_walk(KernelGlobals kg) { return (RT_FETCH(kg, frame, 0u).flags & RT_FLAG_MESH_WALK) != 0u; }
RT_FUNC void rt_kernel_intersect(KernelGlobals kg, uint depth) {
    if (rt_mesh_walk(kg)) return;  // intersect_mesh's
#if defined(RT_WIDE_TRAVERSAL)
    if (RT_FETCH(kg, frame, 0u).bvh_layout == RT_BVH_LAYOUT_WIDE) {
        RT_GRID_RANGES(begin, end, rt_ray_count(kg, depth)) { rt_walk_range(kg, begin, end, depth, false, false); }
        return;
    }
#endif
    RT_WORK_LOOP(kg, i, rt_ray_count(kg, depth), RT_COUNTER_TAKEN_RAYS + depth) {
        rt_stage_trace(kg, i, depth, false, false);
    }
}
RT_FUNC void rt_kernel_occlude(KernelGlobals kg, uint depth) {
    if (rt_mesh_walk(kg)) return;  // occlude_mesh's
#if defined(RT_WIDE_TRAVERSAL)
    if (RT_FETCH(kg, frame, 0u).bvh_layout == RT_BVH_LAYOUT_WIDE) {
        RT_GRID_RANGES(begin, end, rt_ray_count(kg, depth)) { rt_walk_range(kg, begin, end, depth, true, false); }
        return;
    }
#endif
    RT_WORK_LOOP(kg, i, rt_ray_count(kg, depth), RT_COUNTER_TAKEN_RAYS + depth) {
        rt_stage_trace(kg, i, depth, true, false);
    }
}
// One instance in the stack layout (RT_FLAG_MESH_WALK, set for no other layout): the one-mesh walk.
RT_FUNC void rt_kernel_intersect_mesh(KernelGlobals kg, uint depth) {
    if (!rt_mesh_walk(kg)) return;
    RT_WORK_LOOP(kg, i, rt_ray_count(kg, depth), RT_COUNTER_TAKEN_RAYS + depth) {
        rt_stage_trace(kg, i, depth, false, true);
    }
}
RT_FUNC void rt_kernel_occlude_mesh(KernelGlobals kg, uint depth) {
    if (!rt_mesh_walk(kg)) return;
    RT_WORK_LOOP(kg, i, rt_ray_count(kg, depth), RT_COUNTER_TAKEN_RAYS + depth) {
        rt_stage_trace(kg, i, depth, true, true);
    }
}
RT_FUNC void rt_kernel_miss(KernelGlobals kg, uint depth) {
    RT_GRID_LOOP(i, rt_ray_count(kg, depth)) { rt_stage_miss(kg, i, depth); }
}
RT_FUNC void rt_kernel_shade(KernelGlobals kg, uint depth) {
    RT_GRID_LOOP(i, rt_ray_count(kg, depth)) { rt_stage_shade(kg, i, depth); }
}
RT_FUNC void rt_kernel_shadow(KernelGlobals kg, uint depth) {
    if (rt_alpha_shadows(kg)) return;
#if defined(RT_WIDE_TRAVERSAL)
    if (RT_FETCH(kg, frame, 0u).bvh_layout == RT_BVH_LAYOUT_WIDE) {
        RT_GRID_RANGES(begin, end, rt_shadow_count(kg, depth)) { rt_walk_range(kg, begin, end, depth, true, true); }
        return;
    }
#endif
    RT_WORK_LOOP(kg, i, rt_shadow_count(kg, depth), RT_COUNTER_TAKEN_SHADOWS + depth) { rt_stage_shadow(kg, i, depth); }
}
RT_FUNC void rt_kernel_shadow_layers(KernelGlobals kg, uint depth) {
    if (!rt_alpha_shadows(kg)) return;
    RT_WORK_LOOP(kg, i, rt_shadow_count(kg, depth), RT_COUNTER_TAKEN_SHADOWS + depth) {
        rt_stage_shadow_layers(kg, i, depth);
    }
}
RT_FUNC void rt_kernel_resolve(KernelGlobals kg, uint depth) {
    RT_GRID_LOOP(i, rt_pixel_count(kg)) { rt_stage_resolve(kg, i); }
}

#endif
