// kernels/ compiled as OpenCL C 1.2 (PoCL 3.1, NVIDIA OpenCL 3.0). float3/dot/normalize and the operators are
// built in; this header gives the rest of the shared vocabulary.
#ifndef RT_COMPAT_OPENCL_H
#define RT_COMPAT_OPENCL_H

#define RT_FUNC static inline
#define RT_CONST __constant

// A macro that closes the brace its partner opened: clang-format would split it.
// clang-format off
#define RT_STRUCT_BEGIN(name) typedef struct name {
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
RT_FUNC uint rt_mask_le4(float4 a, float4 b) {
    return (a.x <= b.x ? 1u : 0u) | (a.y <= b.y ? 2u : 0u) | (a.z <= b.z ? 4u : 0u) | (a.w <= b.w ? 8u : 0u);
}
RT_FUNC uint rt_mask_lt4(float4 a, float4 b) {
    return (a.x < b.x ? 1u : 0u) | (a.y < b.y ? 2u : 0u) | (a.z < b.z ? 4u : 0u) | (a.w < b.w ? 8u : 0u);
}
RT_FUNC float rt_lane(float4 v, uint k) { return k == 0u ? v.x : (k == 1u ? v.y : (k == 2u ? v.z : v.w)); }
RT_FUNC uint rt_lane_u(uint4 v, uint k) { return k == 0u ? v.x : (k == 1u ? v.y : (k == 2u ? v.z : v.w)); }
typedef struct rt_float8 {
    float4 lo;
    float4 hi;
} rt_float8;
RT_FUNC rt_float8 rt_make8(float4 lo, float4 hi) {
    rt_float8 r;
    r.lo = lo;
    r.hi = hi;
    return r;
}
RT_FUNC rt_float8 rt_splat8(float s) { return rt_make8((float4)(s), (float4)(s)); }
RT_FUNC rt_float8 rt_sub8(rt_float8 a, rt_float8 b) { return rt_make8(a.lo - b.lo, a.hi - b.hi); }
RT_FUNC rt_float8 rt_mul8(rt_float8 a, rt_float8 b) { return rt_make8(a.lo * b.lo, a.hi * b.hi); }
RT_FUNC rt_float8 rt_min8(rt_float8 a, rt_float8 b) { return rt_make8(fmin(a.lo, b.lo), fmin(a.hi, b.hi)); }
RT_FUNC rt_float8 rt_max8(rt_float8 a, rt_float8 b) { return rt_make8(fmax(a.lo, b.lo), fmax(a.hi, b.hi)); }
RT_FUNC uint rt_mask_le8(rt_float8 a, rt_float8 b) { return rt_mask_le4(a.lo, b.lo) | (rt_mask_le4(a.hi, b.hi) << 4); }
RT_FUNC float rt_lane8(rt_float8 v, uint k) { return k < 4u ? rt_lane(v.lo, k) : rt_lane(v.hi, k - 4u); }
RT_FUNC uint rt_lane8_u(uint4 lo, uint4 hi, uint k) { return k < 4u ? rt_lane_u(lo, k) : rt_lane_u(hi, k - 4u); }
RT_FUNC uint rt_lowest_bit(uint x) { return 31u - clz(x & (0u - x)); }
#define rt_abs(a) fabs(a)
#define rt_sqrt(a) sqrt(a)
#define rt_floor(a) floor(a)
#define rt_pow(a, b) pow((a), (b))
#define rt_exp2(a) exp2(a)
#define rt_ldexp(a, e) ldexp((a), (e))
#define rt_atan2(y, x) atan2((y), (x))
#define rt_acos(a) acos(a)
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

#define RT_FETCH(kg, array, i) ((kg).array[(i)])
#define RT_STORE(kg, array, i, value) ((kg).array[(i)] = (value))
#define RT_ATOMIC_ADD(kg, array, i, value) atomic_add(&(kg).array[(i)], (value))
#define RT_PREFETCH(kg, array, i, n) ((void)0)  // a CPU cache hint; GPUs hide latency with other work-items

#define RT_GRID_LOOP(i, n) for (uint i = (uint)get_global_id(0), rt_n_ = (n); i < rt_n_; i += (uint)get_global_size(0))

#endif
