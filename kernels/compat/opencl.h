// kernels/ compiled as OpenCL C 1.2 (PoCL 3.1, NVIDIA OpenCL 3.0). float3/dot/normalize and the operators are
// built in; this header gives the rest of the shared vocabulary.
#ifndef RT_COMPAT_OPENCL_H
#define RT_COMPAT_OPENCL_H

#define RT_FUNC static inline
#define RT_CONST __constant
#define RT_OUT_ARRAY  // an array parameter is a pointer to the caller's array (GLSL says `out`)

// A macro that closes the brace its partner opened: clang-format would split it. Every device struct is 16-aligned
// (a struct of four scalars too), so a row of four can move in one 16-byte load.
// clang-format off
#define RT_STRUCT_BEGIN(name) typedef struct __attribute__((aligned(16))) name {
#define RT_STRUCT_END(name) } name;
// clang-format on

#define make_float2(x, y) ((float2)((x), (y)))
#define make_float3(x, y, z) ((float3)((x), (y), (z)))
#define make_float4(x, y, z, w) ((float4)((x), (y), (z), (w)))
#define make_uint4(x, y, z, w) ((uint4)((x), (y), (z), (w)))

#define rt_min(a, b) fmin((a), (b))
#define rt_max(a, b) fmax((a), (b))
// ---- Lanes (wide BVH nodes, four triangles at a time): fmin/fmax and arithmetic are built in for float4; a mask
// has bit k set for lane k; rt_float8 is two float4 halves (lanes 0-3, 4-7). OpenCL C 1.2 has clz but no ctz.
#define rt_min4(a, b) fmin((a), (b))
#define rt_max4(a, b) fmax((a), (b))
#define rt_abs4(a) fabs(a)
#include "scalar_lanes.h"
RT_FUNC uint rt_lowest_bit(uint x) { return 31u - clz(x & (0u - x)); }
#define rt_abs(a) fabs(a)
#define rt_sqrt(a) sqrt(a)
#define rt_floor(a) floor(a)
#define rt_pow(a, b) pow((a), (b))
#define rt_exp2(a) exp2(a)
#define rt_ldexp(a, e) ldexp((a), (e))
#define rt_atan2(y, x) atan2((y), (x))
#define rt_acos(a) acos(a)
#define rt_cos(a) cos(a)
#define rt_isfinite(a) isfinite(a)
#define rt_min_u(a, b) min((uint)(a), (uint)(b))
#define rt_max_u(a, b) max((uint)(a), (uint)(b))
#define rt_min_i(a, b) min((int)(a), (int)(b))
#define rt_max_i(a, b) max((int)(a), (int)(b))

#define rt_float(x) ((float)(x))
#define rt_uint(x) ((uint)(x))
#define rt_int(x) ((int)(x))
#define rt_as_uint(f) as_uint(f)
#define rt_as_float(u) as_float(u)
#define rt_as_int(f) as_int(f)
#define rt_int_as_float(i) as_float(i)

#define RT_INFINITY INFINITY
#define RT_GLOBAL_PTR(type) __global type*
#define RT_GLOBAL_PTR_ro(type) __global const type*  // an array the stages only read
#define RT_GLOBAL_PTR_rw(type) __global type*

#define RT_FETCH(kg, array, i) ((kg).array[(i)])
#define RT_STORE(kg, array, i, value) ((kg).array[(i)] = (value))
#define RT_ATOMIC_ADD(kg, array, i, value) atomic_add(&(kg).array[(i)], (value))
#define RT_PREFETCH(kg, array, i, n) ((void)0)  // a CPU cache hint; GPUs hide latency with other work-items

// A traversal stage's ray and hit are touched once: on NVIDIA's platform, streaming (evict-first) loads and stores
// in PTX, ld/st.global.cs, 16 bytes at a time, as compat/cuda.h's rt_fetch_once. OpenCL C has no templates, so
// kernels/stages.h instantiates RT_ONCE_ACCESS for each array it streams; the load is not volatile, so the pieces
// of the struct a stage never reads are not loaded. Elsewhere: plain loads and stores.
#if defined(RT_OPENCL_NVIDIA_PTX)
RT_FUNC uint4 rt_ptx_load_once(__global const uint4* p) {
    uint4 v;
    asm("ld.global.cs.v4.u32 {%0,%1,%2,%3}, [%4];" : "=r"(v.x), "=r"(v.y), "=r"(v.z), "=r"(v.w) : "l"(p));
    return v;
}
RT_FUNC void rt_ptx_store_once(__global uint4* p, uint4 v) {
    asm volatile("st.global.cs.v4.u32 [%0], {%1,%2,%3,%4};" ::"l"(p), "r"(v.x), "r"(v.y), "r"(v.z), "r"(v.w)
                 : "memory");
}
// clang-format off
#define RT_ONCE_ACCESS(type, array)                                                                          \
    RT_FUNC type rt_fetch_once_##array(__global const type* p) {                                             \
        union { type value; uint4 piece[sizeof(type) / 16]; } u;                                           \
        for (uint k = 0u; k < sizeof(type) / 16; ++k) u.piece[k] = rt_ptx_load_once((__global const uint4*)p + k); \
        return u.value;                                                                                      \
    }                                                                                                        \
    RT_FUNC void rt_store_once_##array(__global type* p, type value) {                                       \
        union { type value; uint4 piece[sizeof(type) / 16]; } u;                                           \
        u.value = value;                                                                                     \
        for (uint k = 0u; k < sizeof(type) / 16; ++k) rt_ptx_store_once((__global uint4*)p + k, u.piece[k]); \
    }
// clang-format on
#define RT_FETCH_ONCE(kg, array, i) rt_fetch_once_##array((kg).array + (i))
#define RT_STORE_ONCE(kg, array, i, value) rt_store_once_##array((kg).array + (i), (value))
#else
#define RT_FETCH_ONCE(kg, array, i) RT_FETCH(kg, array, i)
#define RT_STORE_ONCE(kg, array, i, value) RT_STORE(kg, array, i, value)
#endif

// n consecutive slots of a queue counter for each work-item (kernels/stages.h, rt_queue_reserve). OpenCL C 1.2
// has no subgroup operations, and NVIDIA's OpenCL has no cl_khr_subgroups: there (RT_OPENCL_NVIDIA_PTX, set by the
// backend for NVIDIA's platform) the warp's work-items sum their n with PTX warp votes and shuffles, as CUDA does,
// and one atomic add takes the warp's slots. Elsewhere each work-item takes its own with one atomic add.
#if defined(RT_OPENCL_NVIDIA_PTX)
RT_FUNC uint rt_ptx_active_mask(void) {
    uint mask;
    asm volatile("activemask.b32 %0;" : "=r"(mask));
    return mask;
}
RT_FUNC uint rt_ptx_lane(void) {
    uint lane;
    asm volatile("mov.u32 %0, %%laneid;" : "=r"(lane));
    return lane;
}
RT_FUNC uint rt_ptx_ballot(uint mask, uint predicate) {
    uint bits;
    asm volatile("{ .reg .pred p; setp.ne.u32 p, %1, 0; vote.sync.ballot.b32 %0, p, %2; }"
                 : "=r"(bits)
                 : "r"(predicate), "r"(mask));
    return bits;
}
RT_FUNC uint rt_ptx_shuffle(uint mask, uint value, uint lane) {
    uint out;
    asm volatile("shfl.sync.idx.b32 %0, %1, %2, 31, %3;" : "=r"(out) : "r"(value), "r"(lane), "r"(mask));
    return out;
}
// The sum of n over the active lanes and over the lanes below this one, a bit of n at a time (n is small).
RT_FUNC uint rt_reserve_warp(__global uint* counter, uint n, bool lane_first) {
    uint active = rt_ptx_active_mask();
    uint lane = rt_ptx_lane();
    uint below = active & ((1u << lane) - 1u);
    uint before = 0u;
    uint total = 0u;
    for (uint bit = 0u; rt_ptx_ballot(active, n >> bit) != 0u; ++bit) {
        uint set = rt_ptx_ballot(active, (n >> bit) & 1u);
        before += popcount(set & below) << bit;
        total += popcount(set) << bit;
    }
    uint leader = 31u - clz(active & (0u - active));
    uint first = 0u;
    if (lane == leader && total != 0u) first = atomic_add(counter, total);
    return rt_ptx_shuffle(active, first, leader) + (lane_first ? before : 0u);
}
#define RT_QUEUE_RESERVE(kg, array, i, n) rt_reserve_warp(&(kg).array[(i)], (n), true)
#define RT_QUEUE_RESERVE_GROUP(kg, array, i, n) rt_reserve_warp(&(kg).array[(i)], (n), false)
// RT_WORK_LOOP's next item (kernels/stages.h), as in cuda.h. Elsewhere, with an atomic add per item and no warp to
// keep busy, the traversal stages keep the grid loop (no RT_FIRST_ITEM).
#define RT_FIRST_ITEM(kg, slot) RT_QUEUE_RESERVE(kg, counters, (slot), 1u)
#define RT_NEXT_ITEM(kg, slot, i) RT_QUEUE_RESERVE(kg, counters, (slot), 1u)
RT_FUNC uint rt_warp_count(bool p, bool below_only) {
    uint set = rt_ptx_ballot(rt_ptx_active_mask(), p ? 1u : 0u);
    return popcount(below_only ? set & ((1u << rt_ptx_lane()) - 1u) : set);
}
#define RT_GROUP_COUNT(p) rt_warp_count((p), false)
#define RT_GROUP_COUNT_BELOW(p) rt_warp_count((p), true)
#else
// Each work-item is its own group.
#define RT_QUEUE_RESERVE(kg, array, i, n) atomic_add(&(kg).array[(i)], (n))
#define RT_QUEUE_RESERVE_GROUP(kg, array, i, n) atomic_add(&(kg).array[(i)], (n))
#define RT_GROUP_COUNT(p) ((p) ? 1u : 0u)
#define RT_GROUP_COUNT_BELOW(p) 0u
#endif

#define RT_GRID_LOOP(i, n) for (uint i = (uint)get_global_id(0), rt_n_ = (n); i < rt_n_; i += (uint)get_global_size(0))

#endif
