// kernels/ compiled as OpenCL C 1.2 (PoCL 3.1, NVIDIA OpenCL 3.0). float3/dot/normalize and the operators are
// built in; this header gives the rest of the shared vocabulary.
#ifndef RT_COMPAT_OPENCL_H
#define RT_COMPAT_OPENCL_H

#define RT_FUNC static inline
#define RT_CONST __constant

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

#define RT_GRID_LOOP(i, n) for (uint i = (uint)get_global_id(0), rt_n_ = (n); i < rt_n_; i += (uint)get_global_size(0))

#endif
