// kernels/ compiled as C++ (host reference, cpu backend, unit tests). Gives C++ the vocabulary that OpenCL C and
// GLSL have built in: float2/3/4, uint2/4, swizzle-free helpers and operators.
#ifndef RT_COMPAT_CPU_H
#define RT_COMPAT_CPU_H

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>

#define RT_FUNC static inline
#define RT_CONST static constexpr

typedef uint32_t uint;

#define RT_STRUCT_BEGIN(name) struct name {
#define RT_STRUCT_END(name) };

struct float2 { float x, y; };
struct float3 { float x, y, z; };
struct float4 { float x, y, z, w; };
struct uint2 { uint x, y; };
struct uint4 { uint x, y, z, w; };

RT_FUNC float2 make_float2(float x, float y) { return float2{x, y}; }
RT_FUNC float3 make_float3(float x, float y, float z) { return float3{x, y, z}; }
RT_FUNC float4 make_float4(float x, float y, float z, float w) { return float4{x, y, z, w}; }
RT_FUNC uint4 make_uint4(uint x, uint y, uint z, uint w) { return uint4{x, y, z, w}; }

// Operators are C++ only; the shared code uses them the way OpenCL C and GLSL provide them natively.
RT_FUNC float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
RT_FUNC float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
RT_FUNC float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
RT_FUNC float3 operator/(float3 a, float3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
RT_FUNC float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
RT_FUNC float3 operator*(float s, float3 a) { return {a.x * s, a.y * s, a.z * s}; }
RT_FUNC float3 operator/(float3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
RT_FUNC float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
RT_FUNC float2 operator+(float2 a, float2 b) { return {a.x + b.x, a.y + b.y}; }
RT_FUNC float2 operator-(float2 a, float2 b) { return {a.x - b.x, a.y - b.y}; }
RT_FUNC float2 operator*(float2 a, float s) { return {a.x * s, a.y * s}; }
RT_FUNC float2 operator*(float s, float2 a) { return {a.x * s, a.y * s}; }
RT_FUNC float4 operator+(float4 a, float4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
RT_FUNC float4 operator*(float4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
RT_FUNC float4 operator*(float s, float4 a) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }

RT_FUNC float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RT_FUNC float3 cross(float3 a, float3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
RT_FUNC float length(float3 a) { return std::sqrt(dot(a, a)); }
RT_FUNC float3 normalize(float3 a) { return a * (1.0f / std::sqrt(dot(a, a))); }

// Scalar math under one spelling for all four languages. min/max are plain comparisons (one minss/maxss), not
// std::fmin/fmax, whose NaN rules cost a library call per use without -ffast-math: the box test calls them 12
// times per node. The kernels never pass NaN to them (rt_safe_inverse keeps slab tests finite).
RT_FUNC float rt_min(float a, float b) { return b < a ? b : a; }
RT_FUNC float rt_max(float a, float b) { return a < b ? b : a; }
#define rt_abs(a) std::fabs(a)
#define rt_sqrt(a) std::sqrt(a)
#define rt_floor(a) std::floor(a)
#define rt_pow(a, b) std::pow((a), (b))
#define rt_exp2(a) std::exp2(a)
#define rt_ldexp(a, e) std::ldexp((a), (e))
#define rt_atan2(y, x) std::atan2((y), (x))
#define rt_acos(a) std::acos(a)
#define rt_isfinite(a) std::isfinite(a)
RT_FUNC uint rt_min_u(uint a, uint b) { return a < b ? a : b; }
RT_FUNC uint rt_max_u(uint a, uint b) { return a > b ? a : b; }
RT_FUNC int rt_min_i(int a, int b) { return a < b ? a : b; }
RT_FUNC int rt_max_i(int a, int b) { return a > b ? a : b; }

// Conversions: GLSL has only constructor syntax, C has only cast syntax.
#define rt_float(x) ((float)(x))
#define rt_uint(x) ((uint)(x))
#define rt_int(x) ((int)(x))
RT_FUNC uint rt_as_uint(float f) { return std::bit_cast<uint>(f); }
RT_FUNC float rt_as_float(uint u) { return std::bit_cast<float>(u); }
RT_FUNC int rt_as_int(float f) { return std::bit_cast<int>(f); }
RT_FUNC float rt_int_as_float(int i) { return std::bit_cast<float>(i); }

#define RT_INFINITY (__builtin_inff())
#define RT_GLOBAL_PTR(type) type*

// Buffers: `kg` is a struct of pointers generated from kernels/data_arrays.h.
#define RT_FETCH(kg, array, i) ((kg).array[(i)])
#define RT_STORE(kg, array, i, value) ((kg).array[(i)] = (value))
// Atomic add on a uint buffer element, returning the old value. atomic_ref keeps the buffers plain arrays.
#define RT_ATOMIC_ADD(kg, array, i, value) (std::atomic_ref<uint>((kg).array[(i)]).fetch_add((value)))

// The grid loop of a stage entry. The cpu backend's thread pool hands each worker chunks of work through
// rt_cpu_next_chunk (backends/cpu), so one worker loop serves every stage.
struct RtCpuGrid {
    std::atomic<uint>* next;   // shared chunk cursor for the current launch
    uint chunk;                // items per chunk
};
extern thread_local RtCpuGrid rt_cpu_grid;
#define RT_GRID_LOOP(i, n)                                                                              \
    for (uint rt_begin_ = rt_cpu_grid.next->fetch_add(rt_cpu_grid.chunk), rt_n_ = (n); rt_begin_ < rt_n_; \
         rt_begin_ = rt_cpu_grid.next->fetch_add(rt_cpu_grid.chunk))                                    \
        for (uint i = rt_begin_, rt_end_ = rt_min_u(rt_begin_ + rt_cpu_grid.chunk, rt_n_); i < rt_end_; ++i)

#endif
