// Lane masks, lane picks and the eight-lane float (two float4 halves, lanes 0-3 and 4-7) in plain code, for the
// compat headers without wide vector registers to map them onto (CUDA, OpenCL C); cpu.h has SSE/AVX versions and
// glsl.h GLSL's own. Included by cuda.h and opencl.h once float4, uint4, make_float4, rt_min4, rt_max4 and RT_FUNC
// are defined.
#ifndef RT_COMPAT_SCALAR_LANES_H
#define RT_COMPAT_SCALAR_LANES_H

RT_FUNC uint rt_mask_le4(float4 a, float4 b) {
    return (a.x <= b.x ? 1u : 0u) | (a.y <= b.y ? 2u : 0u) | (a.z <= b.z ? 4u : 0u) | (a.w <= b.w ? 8u : 0u);
}
RT_FUNC uint rt_mask_lt4(float4 a, float4 b) {
    return (a.x < b.x ? 1u : 0u) | (a.y < b.y ? 2u : 0u) | (a.z < b.z ? 4u : 0u) | (a.w < b.w ? 8u : 0u);
}
#include "lane_bits.h"
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
RT_FUNC rt_float8 rt_splat8(float s) { return rt_make8(make_float4(s, s, s, s), make_float4(s, s, s, s)); }
RT_FUNC rt_float8 rt_sub8(rt_float8 a, rt_float8 b) { return rt_make8(a.lo - b.lo, a.hi - b.hi); }
RT_FUNC rt_float8 rt_mul8(rt_float8 a, rt_float8 b) { return rt_make8(a.lo * b.lo, a.hi * b.hi); }
RT_FUNC rt_float8 rt_min8(rt_float8 a, rt_float8 b) { return rt_make8(rt_min4(a.lo, b.lo), rt_min4(a.hi, b.hi)); }
RT_FUNC rt_float8 rt_max8(rt_float8 a, rt_float8 b) { return rt_make8(rt_max4(a.lo, b.lo), rt_max4(a.hi, b.hi)); }
RT_FUNC uint rt_mask_le8(rt_float8 a, rt_float8 b) { return rt_mask_le4(a.lo, b.lo) | (rt_mask_le4(a.hi, b.hi) << 4); }
RT_FUNC float rt_lane8(rt_float8 v, uint k) { return k < 4u ? rt_lane(v.lo, k) : rt_lane(v.hi, k - 4u); }
RT_FUNC uint rt_lane8_u(uint4 lo, uint4 hi, uint k) { return k < 4u ? rt_lane_u(lo, k) : rt_lane_u(hi, k - 4u); }

#endif  // RT_COMPAT_SCALAR_LANES_H
