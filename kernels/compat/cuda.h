// kernels/ compiled by nvcc. CUDA has float3 etc. but no operators on them: they are defined here, like the
// C++ ones in cpu.h. Math maps to the single-precision intrinsics-free functions (same accuracy as OpenCL's
// default build; see docs/fairness.md for the flags both APIs get).
#ifndef RT_COMPAT_CUDA_H
#define RT_COMPAT_CUDA_H

#define RT_FUNC static __device__ __forceinline__
#define RT_CONST static __device__ constexpr
#define RT_OUT_ARRAY  // an array parameter is a pointer to the caller's array (GLSL says `out`)

typedef unsigned int uint;

// A macro that closes the brace its partner opened: clang-format would split it. Every device struct is 16-aligned
// (a struct of four scalars too), so nvcc moves a row of four in one 16-byte load.
// clang-format off
#define RT_STRUCT_BEGIN(name) struct __align__(16) name {
#define RT_STRUCT_END(name) };
// clang-format on

RT_FUNC float3 operator+(float3 a, float3 b) { return make_float3(a.x + b.x, a.y + b.y, a.z + b.z); }
RT_FUNC float3 operator-(float3 a, float3 b) { return make_float3(a.x - b.x, a.y - b.y, a.z - b.z); }
RT_FUNC float3 operator*(float3 a, float3 b) { return make_float3(a.x * b.x, a.y * b.y, a.z * b.z); }
RT_FUNC float3 operator/(float3 a, float3 b) { return make_float3(a.x / b.x, a.y / b.y, a.z / b.z); }
RT_FUNC float3 operator*(float3 a, float s) { return make_float3(a.x * s, a.y * s, a.z * s); }
RT_FUNC float3 operator*(float s, float3 a) { return make_float3(a.x * s, a.y * s, a.z * s); }
RT_FUNC float3 operator/(float3 a, float s) { return make_float3(a.x / s, a.y / s, a.z / s); }
RT_FUNC float3 operator-(float3 a) { return make_float3(-a.x, -a.y, -a.z); }
RT_FUNC float2 operator+(float2 a, float2 b) { return make_float2(a.x + b.x, a.y + b.y); }
RT_FUNC float2 operator-(float2 a, float2 b) { return make_float2(a.x - b.x, a.y - b.y); }
RT_FUNC float2 operator*(float2 a, float s) { return make_float2(a.x * s, a.y * s); }
RT_FUNC float2 operator*(float s, float2 a) { return make_float2(a.x * s, a.y * s); }
RT_FUNC float4 operator+(float4 a, float4 b) { return make_float4(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w); }
RT_FUNC float4 operator-(float4 a, float4 b) { return make_float4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w); }
RT_FUNC float4 operator*(float4 a, float4 b) { return make_float4(a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w); }
RT_FUNC float4 operator/(float4 a, float4 b) { return make_float4(a.x / b.x, a.y / b.y, a.z / b.z, a.w / b.w); }
RT_FUNC float4 operator*(float4 a, float s) { return make_float4(a.x * s, a.y * s, a.z * s, a.w * s); }
RT_FUNC float4 operator*(float s, float4 a) { return make_float4(a.x * s, a.y * s, a.z * s, a.w * s); }

RT_FUNC float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RT_FUNC float3 cross(float3 a, float3 b) {
    return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
RT_FUNC float length(float3 a) { return sqrtf(dot(a, a)); }
RT_FUNC float3 normalize(float3 a) { return a * rsqrtf(dot(a, a)); }

#define rt_min(a, b) fminf((a), (b))
#define rt_max(a, b) fmaxf((a), (b))
#define rt_abs(a) fabsf(a)
#define rt_sqrt(a) sqrtf(a)
#define rt_floor(a) floorf(a)
#define rt_pow(a, b) powf((a), (b))
#define rt_exp2(a) exp2f(a)
#define rt_ldexp(a, e) ldexpf((a), (e))
#define rt_atan2(y, x) atan2f((y), (x))
#define rt_acos(a) acosf(a)
#define rt_cos(a) cosf(a)
#define rt_isfinite(a) isfinite(a)
// ---- Lanes (wide BVH nodes, four triangles at a time): per-component, as OpenCL C and GLSL have them built in.
// A mask has bit k set for lane k; rt_float8 is two float4 halves (lanes 0-3, 4-7).
RT_FUNC float4 rt_min4(float4 a, float4 b) {
    return make_float4(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z), fminf(a.w, b.w));
}
RT_FUNC float4 rt_max4(float4 a, float4 b) {
    return make_float4(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z), fmaxf(a.w, b.w));
}
RT_FUNC float4 rt_abs4(float4 a) { return make_float4(fabsf(a.x), fabsf(a.y), fabsf(a.z), fabsf(a.w)); }
#include "scalar_lanes.h"
RT_FUNC uint rt_lowest_bit(uint x) { return uint(__ffs(x) - 1); }
RT_FUNC uint rt_min_u(uint a, uint b) { return umin(a, b); }
RT_FUNC uint rt_max_u(uint a, uint b) { return umax(a, b); }
RT_FUNC int rt_min_i(int a, int b) { return min(a, b); }
RT_FUNC int rt_max_i(int a, int b) { return max(a, b); }

#define rt_float(x) ((float)(x))
#define rt_uint(x) ((uint)(x))
#define rt_int(x) ((int)(x))
#define rt_as_uint(f) __float_as_uint(f)
#define rt_as_float(u) __uint_as_float(u)
#define rt_as_int(f) __float_as_int(f)
#define rt_int_as_float(i) __int_as_float(i)

#define RT_INFINITY __int_as_float(0x7f800000)
#define RT_GLOBAL_PTR(type) type* __restrict__
#define RT_GLOBAL_PTR_ro(type) const type* __restrict__  // an array the stages only read
#define RT_GLOBAL_PTR_rw(type) type* __restrict__

// An array the stages only read (`ro` in data_arrays.h: a const pointer in KernelGlobals) is loaded through the
// read-only data path, 16 bytes at a time (ld.global.nc: nvcc emits it for __ldg, not for a const member of a
// struct of pointers). Besides the cache path, ptxas then knows no store in the kernel changes what was loaded and
// schedules the loads more freely: the shade kernel went from 161 to 128 registers (docs/kernels.md has the
// timing). An array the stages write is loaded plainly.
template <typename T>
static __device__ __forceinline__ T rt_fetch(const T* __restrict__ array, uint i) {
    if constexpr (sizeof(T) % 16 == 0) {
        T value;
        const uint4* from = reinterpret_cast<const uint4*>(array + i);
        uint4* to = reinterpret_cast<uint4*>(&value);
#pragma unroll
        for (unsigned k = 0; k < sizeof(T) / 16; ++k) to[k] = __ldg(from + k);
        return value;
    } else {
        return __ldg(array + i);
    }
}
template <typename T>
static __device__ __forceinline__ T rt_fetch(T* __restrict__ array, uint i) {
    return array[i];
}
#define RT_FETCH(kg, array, i) rt_fetch((kg).array, (i))
#define RT_STORE(kg, array, i, value) ((kg).array[(i)] = (value))
// A traversal stage's ray and hit are touched once: streaming (evict-first) loads and stores, ld/st.global.cs, so
// that they pass through the L2 cache without pushing the tree out of it. The load is not volatile (unlike
// __ldcs), so the 16-byte pieces of the struct the stage never reads are not loaded at all.
template <typename T>
static __device__ __forceinline__ T rt_fetch_once(const T* __restrict__ array, uint i) {
    static_assert(sizeof(T) % 16 == 0, "streamed 16 bytes at a time");
    T value;
    const uint4* from = reinterpret_cast<const uint4*>(array + i);
    uint4* to = reinterpret_cast<uint4*>(&value);
#pragma unroll
    for (unsigned k = 0; k < sizeof(T) / 16; ++k)
        asm("ld.global.cs.v4.u32 {%0,%1,%2,%3}, [%4];"
            : "=r"(to[k].x), "=r"(to[k].y), "=r"(to[k].z), "=r"(to[k].w)
            : "l"(from + k));
    return value;
}
template <typename T>
static __device__ __forceinline__ void rt_store_once(T* __restrict__ array, uint i, T value) {
    static_assert(sizeof(T) % 16 == 0, "streamed 16 bytes at a time");
    const uint4* from = reinterpret_cast<const uint4*>(&value);
#pragma unroll
    for (unsigned k = 0; k < sizeof(T) / 16; ++k) __stcs(reinterpret_cast<uint4*>(array + i) + k, from[k]);
}
#define RT_FETCH_ONCE(kg, array, i) rt_fetch_once((kg).array, (i))
#define RT_STORE_ONCE(kg, array, i, value) rt_store_once((kg).array, (i), (value))
#define RT_ATOMIC_ADD(kg, array, i, value) atomicAdd(&(kg).array[(i)], (value))
#define RT_PREFETCH(kg, array, i, n) ((void)0)  // a CPU cache hint; GPUs hide latency with other warps
// n consecutive slots of a queue counter for each thread (kernels/stages.h, rt_queue_reserve): the threads of a
// warp that arrive together sum their n a bit at a time with warp votes (n is small), the first takes all of the
// slots with one atomic add, and each gets its own from there (lane_first), or the first of the warp's
// (RT_QUEUE_RESERVE_GROUP). nvcc aggregates an atomic add of 1 on its own, not one of n; cooperative groups'
// exclusive_scan over the coalesced threads made the sphere's shade stage slower than one atomic per slot had been
// (docs/kernels.md, "Queue slots").
static __device__ __forceinline__ uint rt_reserve_warp(uint* counter, uint n, bool lane_first) {
    uint active = __activemask();
    uint lane = threadIdx.x & 31u;  // the stages' blocks are one-dimensional
    uint below = active & ((1u << lane) - 1u);
    uint before = 0u;
    uint total = 0u;
    for (uint bit = 0u; __ballot_sync(active, n >> bit) != 0u; ++bit) {
        uint set = __ballot_sync(active, (n >> bit) & 1u);
        before += uint(__popc(set & below)) << bit;
        total += uint(__popc(set)) << bit;
    }
    uint leader = uint(__ffs(active)) - 1u;
    uint first = 0u;
    if (lane == leader && total != 0u) first = atomicAdd(counter, total);
    return __shfl_sync(active, first, leader) + (lane_first ? before : 0u);
}
#define RT_QUEUE_RESERVE(kg, array, i, n) rt_reserve_warp(&(kg).array[(i)], (n), true)
#define RT_QUEUE_RESERVE_GROUP(kg, array, i, n) rt_reserve_warp(&(kg).array[(i)], (n), false)
// How many of the warp's active threads have p true: all of them, or those on the lanes below this one.
static __device__ __forceinline__ uint rt_warp_count(bool p, bool below_only) {
    uint set = __ballot_sync(__activemask(), p);
    return uint(__popc(below_only ? set & ((1u << (threadIdx.x & 31u)) - 1u) : set));
}
#define RT_GROUP_COUNT(p) rt_warp_count((p), false)
#define RT_GROUP_COUNT_BELOW(p) rt_warp_count((p), true)

// Grid-stride loop: the backend launches a fixed grid sized to fill the GPU; the item count lives on the device.
#define RT_GRID_LOOP(i, n) \
    for (uint i = blockIdx.x * blockDim.x + threadIdx.x, rt_n_ = (n); i < rt_n_; i += gridDim.x * blockDim.x)
// RT_WORK_LOOP's next item (kernels/stages.h) for each active thread: one queue slot of counter `slot`.
#define RT_FIRST_ITEM(kg, slot) RT_QUEUE_RESERVE(kg, counters, (slot), 1u)
#define RT_NEXT_ITEM(kg, slot, i) RT_QUEUE_RESERVE(kg, counters, (slot), 1u)

#endif
