// kernels/ compiled as GLSL 4.60 compute (glslang → SPIR-V for Vulkan). GLSL has vectors and operators but other
// names, no pointers (buffers are global blocks: `kg` is a dummy), no casts (constructors) and no typedef.
#ifndef RT_COMPAT_GLSL_H
#define RT_COMPAT_GLSL_H

#define RT_FUNC
#define RT_CONST const
// An array a function fills for its caller (the other APIs pass a pointer to the caller's array).
#define RT_OUT_ARRAY out

// A macro that closes the brace its partner opened: clang-format would split it.
// clang-format off
#define RT_STRUCT_BEGIN(name) struct name {
#define RT_STRUCT_END(name) };
// clang-format on

#define float2 vec2
#define float3 vec3
#define float4 vec4
#define uint2 uvec2
#define uint4 uvec4
#define make_float2 vec2
#define make_float3 vec3
#define make_float4 vec4
#define make_uint4 uvec4

#define rt_min(a, b) min((a), (b))
#define rt_max(a, b) max((a), (b))
// ---- Lanes (wide BVH nodes, four triangles at a time): min/max and arithmetic are built in for vec4 and a vec4
// can be indexed; a mask has bit k set for lane k; rt_float8 is two vec4 halves (lanes 0-3, 4-7).
#define rt_min4(a, b) min((a), (b))
#define rt_max4(a, b) max((a), (b))
#define rt_abs4(a) abs(a)
uint rt_mask_le4(vec4 a, vec4 b) {
    return (a.x <= b.x ? 1u : 0u) | (a.y <= b.y ? 2u : 0u) | (a.z <= b.z ? 4u : 0u) | (a.w <= b.w ? 8u : 0u);
}
uint rt_mask_lt4(vec4 a, vec4 b) {
    return (a.x < b.x ? 1u : 0u) | (a.y < b.y ? 2u : 0u) | (a.z < b.z ? 4u : 0u) | (a.w < b.w ? 8u : 0u);
}
// Lane masks kept as bits (bit k: lane k), for code that combines several comparisons before it needs the bits.
#define rt_lanes4 uint
uint rt_lt_lanes4(vec4 a, vec4 b) { return rt_mask_lt4(a, b); }
uint rt_le_lanes4(vec4 a, vec4 b) { return rt_mask_le4(a, b); }
uint rt_and_lanes4(uint a, uint b) { return a & b; }
uint rt_or_lanes4(uint a, uint b) { return a | b; }
uint rt_andnot_lanes4(uint a, uint b) { return ~a & b; }
uint rt_lane_bits4(uint m) { return m; }
#define rt_lane(v, k) ((v)[(k)])
#define rt_lane_u(v, k) ((v)[(k)])
struct rt_float8 {
    vec4 lo;
    vec4 hi;
};
#define rt_make8(lo, hi) rt_float8((lo), (hi))
rt_float8 rt_splat8(float s) { return rt_float8(vec4(s), vec4(s)); }
rt_float8 rt_sub8(rt_float8 a, rt_float8 b) { return rt_float8(a.lo - b.lo, a.hi - b.hi); }
rt_float8 rt_mul8(rt_float8 a, rt_float8 b) { return rt_float8(a.lo * b.lo, a.hi * b.hi); }
rt_float8 rt_min8(rt_float8 a, rt_float8 b) { return rt_float8(min(a.lo, b.lo), min(a.hi, b.hi)); }
rt_float8 rt_max8(rt_float8 a, rt_float8 b) { return rt_float8(max(a.lo, b.lo), max(a.hi, b.hi)); }
uint rt_mask_le8(rt_float8 a, rt_float8 b) { return rt_mask_le4(a.lo, b.lo) | (rt_mask_le4(a.hi, b.hi) << 4); }
float rt_lane8(rt_float8 v, uint k) { return k < 4u ? v.lo[k] : v.hi[k - 4u]; }
uint rt_lane8_u(uvec4 lo, uvec4 hi, uint k) { return k < 4u ? lo[k] : hi[k - 4u]; }
#define rt_lowest_bit(x) uint(findLSB(x))
#define rt_abs(a) abs(a)
#define rt_sqrt(a) sqrt(a)
#define rt_floor(a) floor(a)
#define rt_pow(a, b) pow((a), (b))
#define rt_exp2(a) exp2(a)
#define rt_ldexp(a, e) ldexp((a), (e))
#define rt_atan2(y, x) atan((y), (x))
#define rt_acos(a) acos(a)
#define rt_cos(a) cos(a)
#define rt_isfinite(a) (!isinf(a) && !isnan(a))
#define rt_min_u(a, b) min(uint(a), uint(b))
#define rt_max_u(a, b) max(uint(a), uint(b))
#define rt_min_i(a, b) min(int(a), int(b))
#define rt_max_i(a, b) max(int(a), int(b))

#define rt_float(x) float(x)
#define rt_uint(x) uint(x)
#define rt_int(x) int(x)
#define rt_as_uint(f) floatBitsToUint(f)
#define rt_as_float(u) uintBitsToFloat(u)
#define rt_as_int(f) floatBitsToInt(f)
#define rt_int_as_float(i) intBitsToFloat(i)

#define RT_INFINITY uintBitsToFloat(0x7f800000u)

// The arrays' accessors (kernels/globals.h): rt_fetch_<array> and rt_store_<array> move whole 16-byte rows.
#define RT_FETCH(kg, array, i) rt_fetch_##array(i)
#define RT_STORE(kg, array, i, value) rt_store_##array((i), (value))
#define RT_FETCH_ONCE(kg, array, i) RT_FETCH(kg, array, i)  // GLSL has no streaming (evict-first) access
#define RT_STORE_ONCE(kg, array, i, value) RT_STORE(kg, array, i, value)
#if defined(RT_GLSL_ADDRESS)
#define RT_ATOMIC_ADD(kg, array, i, value) atomicAdd(rt_array_##array().array##_at[(i)], (value))
#else
#define RT_ATOMIC_ADD(kg, array, i, value) atomicAdd(array[(i)], (value))
#endif
#define RT_PREFETCH(kg, array, i, n)  // a CPU cache hint; GPUs hide latency with other invocations
// n consecutive slots of a queue counter for each invocation (kernels/stages.h, rt_queue_reserve): the active
// invocations of a subgroup sum their n, one takes all of the slots with one atomic add, and each gets its own
// from there (lane_first), or the first of the subgroup's (RT_QUEUE_RESERVE_GROUP). kernels/globals.h defines
// rt_reserve_counters with RT_GLSL_RESERVE_FUNCTION once the array exists; the shaders enable the subgroup
// extensions (shaders/common.glsl), which every usable device has (the Vulkan backend checks).
#define RT_QUEUE_RESERVE(kg, array, i, n) rt_reserve_##array((i), (n), true)
#define RT_QUEUE_RESERVE_GROUP(kg, array, i, n) rt_reserve_##array((i), (n), false)
#define RT_GLSL_RESERVE_FUNCTION(array)                                                 \
    uint rt_reserve_##array(uint i, uint n, bool lane_first) {                          \
        uint before = subgroupExclusiveAdd(n);                                          \
        uint total = subgroupAdd(n);                                                    \
        uint first = 0u;                                                                \
        if (subgroupElect() && total != 0u) first = RT_ATOMIC_ADD(kg, array, i, total); \
        return subgroupBroadcastFirst(first) + (lane_first ? before : 0u);              \
    }
// How many of the subgroup's active invocations have p true: all of them, or those below this one.
#define RT_GROUP_COUNT(p) subgroupBallotBitCount(subgroupBallot(p))
#define RT_GROUP_COUNT_BELOW(p) subgroupBallotExclusiveBitCount(subgroupBallot(p))

// The shader must declare layout(local_size_x = ...) BEFORE including kernels/: glslang compiles gl_WorkGroupSize
// as (1, 1, 1), without a diagnostic, in functions defined before that declaration.
#define RT_GRID_LOOP(i, n) \
    for (uint i = gl_GlobalInvocationID.x, rt_n_ = (n); i < rt_n_; i += gl_NumWorkGroups.x * gl_WorkGroupSize.x)
// RT_WORK_LOOP's items (kernels/stages.h): the subgroup's active invocations take one each with one atomic add
// (rt_take_counters: a ballot counts them, where rt_reserve_counters' sums of n are scans), or, where the backend
// sets the specialization constant rt_vk_take_work false (shaders/common.glsl: a CPU device), the grid loop's.
#define RT_GLSL_TAKE_FUNCTION(array)                                                              \
    uint rt_take_##array(uint i) {                                                                \
        uvec4 taking = subgroupBallot(true);                                                      \
        uint first = 0u;                                                                          \
        if (subgroupElect()) first = RT_ATOMIC_ADD(kg, array, i, subgroupBallotBitCount(taking)); \
        return subgroupBroadcastFirst(first) + subgroupBallotExclusiveBitCount(taking);           \
    }
#define RT_FIRST_ITEM(kg, slot) (rt_vk_take_work ? rt_take_counters(slot) : gl_GlobalInvocationID.x)
#define RT_NEXT_ITEM(kg, slot, i) \
    (rt_vk_take_work ? rt_take_counters(slot) : (i) + gl_NumWorkGroups.x * gl_WorkGroupSize.x)

#endif
