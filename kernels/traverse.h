// Two-level BVH traversal (thesis 6.2: a top-level BVH over instances, each leaf an instance whose mesh BVH is
// entered with the ray moved into object space, Algorithm 6-3). One loop walks both levels, because GLSL forbids
// recursion and a nested loop would double the stack. Three node layouts (kernels/types.h): a stack traversal that
// visits the nearer child first, the seed's stackless escape-index walk (thesis 6.4.1), and 8-wide nodes whose
// children are tested together, with leaves of four-triangle blocks (the cpu backends' default: the lanes become
// AVX or SSE registers).
//
// The wide traversal is compiled for the cpu backends only (RT_WIDE_TRAVERSAL). A GPU kernel gets one register
// count, the largest any of its paths needs, whichever layout a frame uses, so a wide path inside would slow every
// GPU frame, and tracing the wide layout on a GPU was slower than the stack layout as well (measured in
// docs/kernels.md).
#ifndef RT_TRAVERSE_H
#define RT_TRAVERSE_H
#if defined(RT_CPU)
#define RT_WIDE_TRAVERSAL 1
#endif

#include "globals.h"
#include "intersect.h"

// A pushed marker that means "leave the instance: restore the world-space ray".
#define RT_STACK_LEAVE_INSTANCE 0xfffffffeu

// The ray as the traversal sees it in the current space (world at the top level, object inside an instance).
RT_STRUCT_BEGIN(TraversalRay)
    float4 origin;  // w = tmin
    float4 direction;
    float4 inv_direction;
RT_STRUCT_END(TraversalRay)

RT_FUNC TraversalRay rt_traversal_ray(float3 origin, float3 direction, float tmin) {
    TraversalRay r;
    r.origin = rt_float4(origin, tmin);
    r.direction = rt_float4(direction, 0.0f);
    r.inv_direction = rt_float4(rt_safe_inverse(direction), 0.0f);
    return r;
}

// The same ray in the instance's object space. t is preserved because the direction is not renormalised.
RT_FUNC TraversalRay rt_ray_to_object(Instance inst, TraversalRay world) {
    float3 o =
        rt_transform_point(inst.world_to_object0, inst.world_to_object1, inst.world_to_object2, rt_xyz(world.origin));
    float3 d = rt_transform_vector(inst.world_to_object0, inst.world_to_object1, inst.world_to_object2,
                                   rt_xyz(world.direction));
    return rt_traversal_ray(o, d, world.origin.w);
}

RT_FUNC Hit rt_no_hit() {
    Hit h;
    h.tuv = make_float4(RT_INFINITY, 0.0f, 0.0f, 0.0f);
    h.instance = RT_NONE;
    h.primitive = RT_NONE;
    h.slot = RT_NONE;
    h.unused = 0u;
    return h;
}

// Coplanar overlapping triangles (trim on a wall, a frame in its opening) are hit at one distance that each API
// rounds its own way (FMA contraction, division), so which of them is "nearer" would differ between backends and
// between traversal orders. Hits within RT_TIE_EPSILON (relative) of the best count as one distance, and the lower
// instance, then primitive, wins, whichever the traversal met first; boxes and triangles are tested up to the end
// of that band (rt_hit_reach), never past the ray's tmax.
#define RT_TIE_EPSILON 1e-5f

RT_FUNC float rt_hit_reach(Hit best, float tmax) { return rt_min(best.tuv.x + best.tuv.x * RT_TIE_EPSILON, tmax); }

// Whether a hit at t on (instance, primitive) replaces `best`. A best at +inf or at the ray's tmax has no
// instance (RT_NONE), so any hit in reach replaces it.
RT_FUNC bool rt_hit_wins(float t, uint instance, uint primitive, Hit best) {
    float band = best.tuv.x * RT_TIE_EPSILON;
    if (t < best.tuv.x - band) return true;
    if (t > best.tuv.x + band) return false;
    return instance < best.instance || (instance == best.instance && primitive < best.primitive);
}

// Tests the triangles [first, first + count) and returns the winning hit (or `best` unchanged).
// The hit keeps the triangle's slot in `triangles` so shading can rebuild its geometric normal.
RT_FUNC Hit rt_intersect_leaf(KernelGlobals kg, Hit best, TraversalRay ray, float tmax, uint instance, uint first,
                              uint count) {
    for (uint k = 0u; k < count; ++k) {
        TriangleGeometry tri = RT_FETCH(kg, triangles, first + k);
        float4 h = rt_intersect_triangle(tri, rt_xyz(ray.origin), rt_xyz(ray.direction), ray.origin.w,
                                         rt_hit_reach(best, tmax));
        if (h.x < RT_INFINITY && rt_hit_wins(h.x, instance, rt_as_uint(tri.v0.w), best)) {
            best.tuv = make_float4(h.x, h.y, h.z, 0.0f);
            best.instance = instance;
            best.primitive = rt_as_uint(tri.v0.w);
            best.slot = first + k;
        }
    }
    return best;
}

#if defined(RT_WIDE_TRAVERSAL)
// The traversal's instance while it walks a flattened world BVH (RT_FLAG_FLAT_INSTANCES): each block lane names
// its own.
#define RT_INSTANCE_PER_LANE 0xfffffffdu

// The wide layout's leaves: rt_intersect_leaf a block of four triangles at a time, with the same per-triangle
// results and the same winner (rt_hit_wins).
RT_FUNC_INLINE Hit rt_intersect_blocks(KernelGlobals kg, Hit best, TraversalRay ray, float tmax, uint instance,
                                       uint first, uint count) {
    for (uint b = 0u; b < (count + 3u) / 4u; ++b) {
        TriangleBlock block = RT_FETCH(kg, triangle_blocks, first + b);
        TriangleHits4 hits = rt_intersect_triangles4(block, rt_xyz(ray.origin), rt_xyz(ray.direction), ray.origin.w,
                                                     rt_hit_reach(best, tmax));
        uint mask = hits.mask;
        while (mask != 0u) {
            uint k = rt_lowest_bit(mask);
            mask &= mask - 1u;
            float t = rt_lane_distance(hits, k);
            uint hit_instance = instance == RT_INSTANCE_PER_LANE ? rt_lane_u(block.instance, k) : instance;
            if (rt_hit_wins(t, hit_instance, rt_lane_u(block.primitive, k), best)) {
                best.tuv = make_float4(t, rt_lane(hits.u, k), rt_lane(hits.v, k), 0.0f);
                best.instance = hit_instance;
                best.primitive = rt_lane_u(block.primitive, k);
                best.slot = rt_lane_u(block.slot, k);
            }
        }
    }
    return best;
}

#endif  // RT_WIDE_TRAVERSAL

// The node count the stack walk sets when it has no child to go to: pop the next node.
#define RT_STACK_POP 0xffffffffu

// Stack layout: interior nodes hold their first child (the second is next to it); both child boxes are tested
// and the nearer is visited first, the farther pushed with its entry distance so it can be skipped later.
// - The walk keeps the node it goes to as its parent's pair holds it (first, count): descending costs one
//   dependent load (the pair), not two (the node again, then its pair); only a popped node is fetched again, and
//   in an any-hit walk not even that (its entries are the pair's (first, count), below).
// - "While-while" (Aila & Laine 2009): an inner loop walks interior nodes until every ray has a leaf (or nothing)
//   next, then the rays test their leaves together. With one loop that took a node or a leaf per step, a GPU warp
//   whose rays were at both ran both paths every step (docs/kernels.md, "The stack traversal", has the gain).
// - A scene whose top level holds one instance starts inside it (one_instance: RT_FLAG_ONE_INSTANCE), and an
//   instance with the identity transform keeps the world ray, so a one-mesh scene pays no top-level walk.
RT_FUNC Hit rt_trace_stack(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax, bool any_hit,
                           bool one_instance) {
    Hit best = rt_no_hit();
    best.tuv.x = tmax;
    TraversalRay world = rt_traversal_ray(origin, direction, tmin);
    TraversalRay ray = world;
    uint instance = RT_NONE;
    // An entry is (node, entry distance's bits): a push or a pop moves one 8-byte pair.
    uint2 stack[RT_BVH_STACK_SIZE];
    uint sp = 0u;

    uint root = 0u;
    if (one_instance) {
        Instance inst = RT_FETCH(kg, instances, 0u);
        if ((inst.flags & RT_INSTANCE_IDENTITY) == 0u) ray = rt_ray_to_object(inst, world);
        instance = 0u;
        root = inst.root;
    }
    BvhNode node = RT_FETCH(kg, nodes, root);
    uint first = rt_as_uint(node.lower.w);
    uint count = rt_as_uint(node.upper.w);
    bool going = rt_intersect_node(node, rt_xyz(ray.origin), rt_xyz(ray.inv_direction), tmin, tmax) < RT_INFINITY;
    while (going) {
        // Walk interior nodes until a leaf (or nothing) is next.
        while (count == 0u) {
            float reach = rt_hit_reach(best, tmax);
            BvhNode a = RT_FETCH(kg, nodes, first);
            BvhNode b = RT_FETCH(kg, nodes, first + 1u);
            float t_a = rt_intersect_node(a, rt_xyz(ray.origin), rt_xyz(ray.inv_direction), tmin, reach);
            float t_b = rt_intersect_node(b, rt_xyz(ray.origin), rt_xyz(ray.inv_direction), tmin, reach);
            bool a_first = t_a <= t_b;
            float t_far = rt_max(t_a, t_b);
            if (t_far < RT_INFINITY && sp < rt_uint(RT_BVH_STACK_SIZE)) {
                if (any_hit) {
                    // An any-hit walk visits every entry it pushes (its reach is tmax until the hit it returns
                    // at), so it needs no distance: it pushes the farther child as the pair holds it (first,
                    // count), and its pop loads no node.
                    stack[sp].x = rt_as_uint(a_first ? b.lower.w : a.lower.w);
                    stack[sp].y = rt_as_uint(a_first ? b.upper.w : a.upper.w);
                } else {
                    stack[sp].x = a_first ? first + 1u : first;
                    stack[sp].y = rt_as_uint(t_far);
                }
                sp += 1u;
            }
            if (rt_min(t_a, t_b) < RT_INFINITY) {
                first = rt_as_uint(a_first ? a.lower.w : b.lower.w);
                count = rt_as_uint(a_first ? a.upper.w : b.upper.w);
            } else {
                count = RT_STACK_POP;
            }
        }
        if (count != RT_STACK_POP) {
            if (!one_instance && instance == RT_NONE) {
                // A top-level leaf holds one instance: enter its mesh BVH in object space.
                Instance inst = RT_FETCH(kg, instances, first);
                TraversalRay object_ray = rt_ray_to_object(inst, world);
                BvhNode mesh_root = RT_FETCH(kg, nodes, inst.root);
                if (sp < rt_uint(RT_BVH_STACK_SIZE) &&
                    rt_intersect_node(mesh_root, rt_xyz(object_ray.origin), rt_xyz(object_ray.inv_direction), tmin,
                                      rt_hit_reach(best, tmax)) < RT_INFINITY) {
                    stack[sp].x = RT_STACK_LEAVE_INSTANCE;
                    stack[sp].y = 0u;
                    sp += 1u;
                    ray = object_ray;
                    instance = first;
                    first = rt_as_uint(mesh_root.lower.w);
                    count = rt_as_uint(mesh_root.upper.w);
                    continue;
                }
            } else {
                best = rt_intersect_leaf(kg, best, ray, tmax, instance, first, count);
                if (any_hit && best.instance != RT_NONE) return best;
            }
        }
        // Pop the next node that can still hold a closer hit.
        going = false;
        while (sp > 0u && !going) {
            sp -= 1u;
            uint2 popped = stack[sp];
            if (!one_instance && popped.x == RT_STACK_LEAVE_INSTANCE) {
                ray = world;
                instance = RT_NONE;
            } else if (any_hit) {
                first = popped.x;
                count = popped.y;
                going = true;
            } else if (rt_as_float(popped.y) <= rt_hit_reach(best, tmax)) {
                BvhNode next = RT_FETCH(kg, nodes, popped.x);
                first = rt_as_uint(next.lower.w);
                count = rt_as_uint(next.upper.w);
                going = true;
            }
        }
    }
    if (best.instance == RT_NONE) best.tuv.x = RT_INFINITY;
    return best;
}

// Escape layout (the seed's stackless order): nodes in depth-first order, the left child right after its parent;
// a missed box or a finished leaf jumps to the node's escape index. Entering an instance remembers where the top
// level resumes; reaching the end of the mesh BVH goes back there.
RT_FUNC Hit rt_trace_escape(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax, bool any_hit) {
    Hit best = rt_no_hit();
    best.tuv.x = tmax;
    TraversalRay world = rt_traversal_ray(origin, direction, tmin);
    TraversalRay ray = world;
    uint instance = RT_NONE;
    uint index = 0u;
    uint end = rt_as_uint(RT_FETCH(kg, nodes, 0u).lower.w);
    uint top_resume = 0u;
    uint top_end = end;
    while (true) {
        if (index >= end) {
            if (instance == RT_NONE) break;
            ray = world;
            instance = RT_NONE;
            index = top_resume;
            end = top_end;
            continue;
        }
        BvhNode node = RT_FETCH(kg, nodes, index);
        uint escape = rt_as_uint(node.lower.w);
        uint info = rt_as_uint(node.upper.w);
        float t =
            rt_intersect_node(node, rt_xyz(ray.origin), rt_xyz(ray.inv_direction), tmin, rt_hit_reach(best, tmax));
        if (!(t < RT_INFINITY)) {
            index = escape;
        } else if (info == RT_ESCAPE_INTERIOR) {
            index += 1u;
        } else if (instance == RT_NONE) {
            uint leaf_first = info & RT_ESCAPE_FIRST_MASK;
            Instance inst = RT_FETCH(kg, instances, leaf_first);
            ray = rt_ray_to_object(inst, world);
            instance = leaf_first;
            top_resume = escape;
            index = inst.root;
            end = rt_as_uint(RT_FETCH(kg, nodes, index).lower.w);
        } else {
            best = rt_intersect_leaf(kg, best, ray, tmax, instance, info & RT_ESCAPE_FIRST_MASK,
                                     info >> RT_ESCAPE_COUNT_SHIFT);
            if (any_hit && best.instance != RT_NONE) return best;
            index = escape;
        }
    }
    if (best.instance == RT_NONE) best.tuv.x = RT_INFINITY;
    return best;
}

#if defined(RT_WIDE_TRAVERSAL)
// An instance whose transform is the identity keeps the world ray (and its inverse direction) as it is.
RT_FUNC TraversalRay rt_wide_ray_to_object(Instance inst, TraversalRay world) {
    return (inst.flags & RT_INSTANCE_IDENTITY) != 0u ? world : rt_ray_to_object(inst, world);
}

// A pushed entry is visited later: start loading its node or its leaf's triangles now.
RT_FUNC void rt_wide_prefetch(KernelGlobals kg, uint entry) {
    if ((entry & RT_WIDE_LEAF) == 0u) {
        RT_PREFETCH(kg, wide_nodes, entry, 1u);
    } else if (entry != RT_STACK_LEAVE_INSTANCE) {
        RT_PREFETCH(kg, triangle_blocks, (entry & ~RT_WIDE_LEAF) >> 3u, (entry & 7u) / 4u + 1u);
    }
}

RT_FUNC uint rt_wide_child(BvhWideNode node, uint k) { return rt_lane8_u(node.child0, node.child1, k); }

// Wide layout: a node tests its eight children at once and the traversal goes on with the nearest child entered;
// a second one is pushed, and with three or more all are pushed and sorted, nearest on top (Embree's order). A
// stack entry is a child reference as the node stores it (a node index, or a leaf with its range); a popped entry
// beyond the closest hit so far is skipped. At the top level a leaf is an instance: entering it pushes the leave
// marker, as in the stack layout.
// A scene whose top level holds one instance starts inside it (one_instance: frame flag RT_FLAG_ONE_INSTANCE), and
// an instance with the identity transform keeps the world ray: the traversal then costs what a one-level BVH costs.
// A scene with flattened instances (flat: RT_FLAG_FLAT_INSTANCES) is one world-space BVH: the walk starts "inside"
// at node 0 with the world ray and never meets a top-level leaf; each hit takes its instance from its block.
//
// The walk is a state advanced one node or one leaf at a time (rt_wide_step), so that the cpu backends' traversal
// stages can walk two rays in turn (rt_walk_range, kernels/stages.h). The state that each step reads first (where
// the walk is, WidePosition) is the step's result, so it stays in registers; the rest (the best hit and the rays,
// WideWalk) and the stack are the caller's.
RT_STRUCT_BEGIN(WideWalk)
    Hit best;
    TraversalRay world;
    TraversalRay ray;  // in the current space: world at the top level, object inside an instance
RT_STRUCT_END(WideWalk)

// Where a walk is: what each step reads first, returned by the step so that it stays in registers.
RT_STRUCT_BEGIN(WidePosition)
    uint current;  // the node or leaf the next step visits
    uint sp;
    uint instance;
    uint going;  // 0 once the walk is done
RT_STRUCT_END(WidePosition)

RT_FUNC WideWalk rt_wide_start(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax,
                               bool one_instance) {
    WideWalk w;
    w.best = rt_no_hit();
    w.best.tuv.x = tmax;
    w.world = rt_traversal_ray(origin, direction, tmin);
    w.ray = w.world;
    // The top level holds one instance: start inside it (its mesh root's boxes are tested anyway).
    if (one_instance) w.ray = rt_wide_ray_to_object(RT_FETCH(kg, instances, 0u), w.world);
    return w;
}

RT_FUNC WidePosition rt_wide_start_position(KernelGlobals kg, bool one_instance, bool flat) {
    WidePosition p;
    p.current = 0u;
    p.sp = 0u;
    p.instance = RT_NONE;
    p.going = 1u;
    if (flat) {
        p.instance = RT_INSTANCE_PER_LANE;
    } else if (one_instance) {
        p.instance = 0u;
        p.current = RT_FETCH(kg, instances, 0u).root;
    }
    return p;
}

// One step: the node or leaf p.current, then, unless it leads on to a child, the next entry popped that can still
// hold a closer hit (the walk is done when none is left). An entry is (child reference, entry distance's bits):
// the sort below moves one 8-byte pair per step.
RT_FUNC_INLINE WidePosition rt_wide_step(KernelGlobals kg, WidePosition p, RT_OUT_ARRAY WideWalk* w,
                                         RT_OUT_ARRAY uint2* stack, float tmin, float tmax, bool any_hit) {
    uint sp = p.sp;
    bool descend = false;
    if ((p.current & RT_WIDE_LEAF) == 0u) {
        BvhWideNode node = RT_FETCH(kg, wide_nodes, p.current);
        WideBoxHits hits = rt_intersect_wide_node(node, rt_xyz(w->ray.origin), rt_xyz(w->ray.inv_direction), tmin,
                                                  rt_min(rt_hit_reach(w->best, tmax), RT_FLT_MAX));
        uint mask = hits.mask;
        if (mask != 0u) {
            uint k0 = rt_lowest_bit(mask);
            mask &= mask - 1u;
            uint e0 = rt_wide_child(node, k0);
            descend = true;
            if (mask == 0u) {
                p.current = e0;
            } else {
                float t0 = rt_lane8(hits.t, k0);
                uint k1 = rt_lowest_bit(mask);
                mask &= mask - 1u;
                uint e1 = rt_wide_child(node, k1);
                float t1 = rt_lane8(hits.t, k1);
                if (mask == 0u) {
                    // Two: go on with the nearer, push the farther.
                    if (sp < rt_uint(RT_BVH_WIDE_STACK_SIZE)) {
                        stack[sp].x = t0 <= t1 ? e1 : e0;
                        stack[sp].y = rt_as_uint(rt_max(t0, t1));
                        rt_wide_prefetch(kg, stack[sp].x);
                        sp += 1u;
                    }
                    p.current = t0 <= t1 ? e0 : e1;
                } else if ((mask & (mask - 1u)) == 0u && sp + 3u <= rt_uint(RT_BVH_WIDE_STACK_SIZE)) {
                    // Three (the usual case of "more than two"): each goes straight to its rank, the number of
                    // the others that belong below it — farther, or as far and earlier in lane order, the order
                    // the sort below gives ties, so equal hits keep their winner. Compares instead of the
                    // sort's data-dependent branches, which mispredict on diffuse rays.
                    uint k2 = rt_lowest_bit(mask);
                    uint e2 = rt_wide_child(node, k2);
                    float t2 = rt_lane8(hits.t, k2);
                    uint r0 = sp + (t1 > t0 ? 1u : 0u) + (t2 > t0 ? 1u : 0u);
                    uint r1 = sp + (t0 >= t1 ? 1u : 0u) + (t2 > t1 ? 1u : 0u);
                    uint r2 = sp + (t0 >= t2 ? 1u : 0u) + (t1 >= t2 ? 1u : 0u);
                    stack[r0].x = e0;
                    stack[r0].y = rt_as_uint(t0);
                    stack[r1].x = e1;
                    stack[r1].y = rt_as_uint(t1);
                    stack[r2].x = e2;
                    stack[r2].y = rt_as_uint(t2);
                    rt_wide_prefetch(kg, e0);
                    rt_wide_prefetch(kg, e1);
                    rt_wide_prefetch(kg, e2);
                    sp += 2u;
                    p.current = stack[sp].x;
                } else {
                    // Four or more: push all, sorted so the nearest is on top, and take it.
                    uint first_pushed = sp;
                    mask |= (1u << k0) | (1u << k1);
                    while (mask != 0u) {
                        uint k = rt_lowest_bit(mask);
                        mask &= mask - 1u;
                        if (sp >= rt_uint(RT_BVH_WIDE_STACK_SIZE)) continue;
                        float t = rt_lane8(hits.t, k);
                        uint slot = sp;
                        while (slot > first_pushed && rt_as_float(stack[slot - 1u].y) < t) {
                            stack[slot] = stack[slot - 1u];
                            slot -= 1u;
                        }
                        stack[slot].x = rt_wide_child(node, k);
                        stack[slot].y = rt_as_uint(t);
                        rt_wide_prefetch(kg, stack[slot].x);
                        sp += 1u;
                    }
                    sp -= 1u;
                    p.current = stack[sp].x;
                }
            }
        }
    } else {
        uint first = (p.current & ~RT_WIDE_LEAF) >> 3u;
        if (p.instance == RT_NONE) {
            // A top-level leaf: enter the instance's mesh BVH in object space (t is preserved).
            p.instance = first;
            Instance inst = RT_FETCH(kg, instances, p.instance);
            w->ray = rt_wide_ray_to_object(inst, w->world);
            p.current = inst.root;
            // The leave marker restores the world ray for the entries below it; with none, the walk ends
            // with this instance and needs no marker (a ray that enters one instance only).
            if (sp > 0u && sp < rt_uint(RT_BVH_WIDE_STACK_SIZE)) {
                stack[sp].x = RT_STACK_LEAVE_INSTANCE;
                stack[sp].y = 0u;
                sp += 1u;
            }
            descend = true;
        } else {
            uint count = (p.current & 7u) + 1u;
            w->best = rt_intersect_blocks(kg, w->best, w->ray, tmax, p.instance, first, count);
            if (any_hit && w->best.instance != RT_NONE) sp = 0u;
        }
    }
    if (!descend) {
        // Pop the next entry that can still hold a closer hit.
        bool going = false;
        while (sp > 0u && !going) {
            sp -= 1u;
            uint2 popped = stack[sp];
            if (popped.x == RT_STACK_LEAVE_INSTANCE) {
                w->ray = w->world;
                p.instance = RT_NONE;
            } else if (rt_as_float(popped.y) <= rt_hit_reach(w->best, tmax)) {
                p.current = popped.x;
                going = true;
            }
        }
        p.going = going ? 1u : 0u;
    }
    p.sp = sp;
    return p;
}

RT_FUNC Hit rt_wide_result(WideWalk w) {
    Hit best = w.best;
    if (best.instance == RT_NONE) best.tuv.x = RT_INFINITY;
    return best;
}

RT_FUNC Hit rt_trace_wide(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax, bool any_hit,
                          bool one_instance, bool flat) {
    uint2 stack[RT_BVH_WIDE_STACK_SIZE];
    WideWalk w = rt_wide_start(kg, origin, direction, tmin, tmax, one_instance && !flat);
    WidePosition p = rt_wide_start_position(kg, one_instance, flat);
    while (p.going != 0u) p = rt_wide_step(kg, p, &w, stack, tmin, tmax, any_hit);
    return rt_wide_result(w);
}

#endif  // RT_WIDE_TRAVERSAL

// The stack layout's walk of a scene of one instance (RT_FLAG_MESH_WALK): rt_trace_stack with one_instance a
// constant, so the kernel that calls it holds no code for entering or leaving instances and keeps no world ray.
RT_FUNC Hit rt_trace_mesh(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax, bool any_hit) {
    return rt_trace_stack(kg, origin, direction, tmin, tmax, any_hit, true);
}

RT_FUNC Hit rt_trace(KernelGlobals kg, float3 origin, float3 direction, float tmin, float tmax, bool any_hit) {
    // The frame is loaded whole: Mesa 22.3's lavapipe, in the Vulkan backend's buffer-address mode, read
    // the frame's bvh_layout (a single field fetched from the frame array) as its instance count after the stage had
    // loaded the frame.
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    uint bvh_layout = frame.bvh_layout;
#if defined(RT_WIDE_TRAVERSAL)
    if (bvh_layout == RT_BVH_LAYOUT_WIDE)
        return rt_trace_wide(kg, origin, direction, tmin, tmax, any_hit, (frame.flags & RT_FLAG_ONE_INSTANCE) != 0u,
                             (frame.flags & RT_FLAG_FLAT_INSTANCES) != 0u);
#endif
    // (A GPU backend never receives a wide scene: RenderEngine refuses it.)
    if (bvh_layout == RT_BVH_LAYOUT_ESCAPE) return rt_trace_escape(kg, origin, direction, tmin, tmax, any_hit);
    return rt_trace_stack(kg, origin, direction, tmin, tmax, any_hit, (frame.flags & RT_FLAG_ONE_INSTANCE) != 0u);
}

#endif
