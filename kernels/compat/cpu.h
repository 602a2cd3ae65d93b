// kernels/ compiled as C++ (host reference, cpu backend, unit tests). Gives C++ the vocabulary that OpenCL C and
// GLSL have built in: float2/3/4, uint2/4, swizzle-free helpers and operators.
#ifndef RT_COMPAT_CPU_H
#define RT_COMPAT_CPU_H

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#define RT_FUNC static inline
// A function the compiler must inline (the cpu backends' wide walk: its step, its leaf test, a walk's advance in
// rt_walk_range). Called, they pass the walk's state through memory, and GCC 12 chose to call them there.
#define RT_FUNC_INLINE static inline __attribute__((always_inline))
#define RT_CONST static constexpr
#define RT_OUT_ARRAY  // an array parameter is a pointer to the caller's array (GLSL says `out`)

typedef uint32_t uint;

// A macro that closes the brace its partner opened: clang-format would split it. Every device struct is 16-aligned
// (a struct of four scalars too), so a compiler may move it in 16-byte loads.
// clang-format off
#define RT_STRUCT_BEGIN(name) struct alignas(16) name {
#define RT_STRUCT_END(name) };
// clang-format on

struct float2 {
    float x, y;
};
struct float3 {
    float x, y, z;
};
struct float4 {
    float x, y, z, w;
};
struct uint2 {
    uint x, y;
};
struct uint4 {
    uint x, y, z, w;
};

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
#define rt_cos(a) std::cos(a)
#define rt_isfinite(a) std::isfinite(a)
RT_FUNC uint rt_min_u(uint a, uint b) { return a < b ? a : b; }
RT_FUNC uint rt_max_u(uint a, uint b) { return a > b ? a : b; }
RT_FUNC int rt_min_i(int a, int b) { return a < b ? a : b; }
RT_FUNC int rt_max_i(int a, int b) { return a > b ? a : b; }

// ---- Lanes: float4 arithmetic and 8-lane vectors (wide BVH nodes, four triangles at a time) ----
// float4 maps to one SSE register (every x86-64 CPU has SSE2); rt_float8 (two float4 halves, as the nodes store
// them) to one AVX register where the translation unit is compiled for AVX (the cpu backend's AVX2 stages), else
// to two SSE registers; elsewhere to plain per-component code. memcpy moves bytes between the structs and registers
// without an aliasing question, and the compiler keeps the values in registers; std::bit_cast does not do as well:
// with it GCC 12 stored each AVX value to the stack and read it back in 8-byte pieces, a store-forwarding stall per
// operation that made the AVX2 traversal several times slower (docs/kernels.md, "The wide layout"). min/max pick per
// lane as rt_min/rt_max do (minps(b, a) is b < a ? b : a); a mask has bit k set for lane k.
struct rt_float8 {
    float4 lo, hi;  // lanes 0-3, 4-7
};
template <typename To, typename From>
RT_FUNC To rt_copy_bits(From from) {
    static_assert(sizeof(To) == sizeof(From));
    To to;
    std::memcpy(&to, &from, sizeof to);
    return to;
}
#if defined(__SSE2__)
RT_FUNC __m128 rt_sse(float4 a) { return rt_copy_bits<__m128>(a); }
RT_FUNC float4 rt_from_sse(__m128 v) { return rt_copy_bits<float4>(v); }
RT_FUNC float4 operator+(float4 a, float4 b) { return rt_from_sse(_mm_add_ps(rt_sse(a), rt_sse(b))); }
RT_FUNC float4 operator-(float4 a, float4 b) { return rt_from_sse(_mm_sub_ps(rt_sse(a), rt_sse(b))); }
RT_FUNC float4 operator*(float4 a, float4 b) { return rt_from_sse(_mm_mul_ps(rt_sse(a), rt_sse(b))); }
RT_FUNC float4 operator/(float4 a, float4 b) { return rt_from_sse(_mm_div_ps(rt_sse(a), rt_sse(b))); }
RT_FUNC float4 rt_min4(float4 a, float4 b) { return rt_from_sse(_mm_min_ps(rt_sse(b), rt_sse(a))); }
RT_FUNC float4 rt_max4(float4 a, float4 b) { return rt_from_sse(_mm_max_ps(rt_sse(b), rt_sse(a))); }
RT_FUNC float4 rt_abs4(float4 a) { return rt_from_sse(_mm_andnot_ps(_mm_set1_ps(-0.0f), rt_sse(a))); }
RT_FUNC uint rt_mask_le4(float4 a, float4 b) { return uint(_mm_movemask_ps(_mm_cmple_ps(rt_sse(a), rt_sse(b)))); }
RT_FUNC uint rt_mask_lt4(float4 a, float4 b) { return uint(_mm_movemask_ps(_mm_cmplt_ps(rt_sse(a), rt_sse(b)))); }
// A lane mask held as a comparison result (all ones or zeros per lane) while several combine, turned into bits
// once (rt_lane_bits4): the four-triangle test combines thirteen comparisons into two masks.
typedef __m128 rt_lanes4;
RT_FUNC rt_lanes4 rt_lt_lanes4(float4 a, float4 b) { return _mm_cmplt_ps(rt_sse(a), rt_sse(b)); }
RT_FUNC rt_lanes4 rt_le_lanes4(float4 a, float4 b) { return _mm_cmple_ps(rt_sse(a), rt_sse(b)); }
RT_FUNC rt_lanes4 rt_and_lanes4(rt_lanes4 a, rt_lanes4 b) { return _mm_and_ps(a, b); }
RT_FUNC rt_lanes4 rt_or_lanes4(rt_lanes4 a, rt_lanes4 b) { return _mm_or_ps(a, b); }
RT_FUNC rt_lanes4 rt_andnot_lanes4(rt_lanes4 a, rt_lanes4 b) { return _mm_andnot_ps(a, b); }
RT_FUNC uint rt_lane_bits4(rt_lanes4 m) { return uint(_mm_movemask_ps(m)); }
#else
RT_FUNC float4 operator+(float4 a, float4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
RT_FUNC float4 operator-(float4 a, float4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
RT_FUNC float4 operator*(float4 a, float4 b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }
RT_FUNC float4 operator/(float4 a, float4 b) { return {a.x / b.x, a.y / b.y, a.z / b.z, a.w / b.w}; }
RT_FUNC float4 rt_min4(float4 a, float4 b) {
    return {rt_min(a.x, b.x), rt_min(a.y, b.y), rt_min(a.z, b.z), rt_min(a.w, b.w)};
}
RT_FUNC float4 rt_max4(float4 a, float4 b) {
    return {rt_max(a.x, b.x), rt_max(a.y, b.y), rt_max(a.z, b.z), rt_max(a.w, b.w)};
}
RT_FUNC float4 rt_abs4(float4 a) { return {rt_abs(a.x), rt_abs(a.y), rt_abs(a.z), rt_abs(a.w)}; }
RT_FUNC uint rt_mask_le4(float4 a, float4 b) {
    return (a.x <= b.x ? 1u : 0u) | (a.y <= b.y ? 2u : 0u) | (a.z <= b.z ? 4u : 0u) | (a.w <= b.w ? 8u : 0u);
}
RT_FUNC uint rt_mask_lt4(float4 a, float4 b) {
    return (a.x < b.x ? 1u : 0u) | (a.y < b.y ? 2u : 0u) | (a.z < b.z ? 4u : 0u) | (a.w < b.w ? 8u : 0u);
}
#include "lane_bits.h"
#endif
RT_FUNC float rt_lane(float4 v, uint k) {
    float lanes[4];
    std::memcpy(lanes, &v, sizeof lanes);
    return lanes[k];
}
RT_FUNC uint rt_lane_u(uint4 v, uint k) {
    uint lanes[4];
    std::memcpy(lanes, &v, sizeof lanes);
    return lanes[k];
}

RT_FUNC rt_float8 rt_make8(float4 lo, float4 hi) { return rt_float8{lo, hi}; }
RT_FUNC rt_float8 rt_splat8(float s) { return rt_float8{float4{s, s, s, s}, float4{s, s, s, s}}; }
#if defined(__AVX__)
RT_FUNC __m256 rt_avx(rt_float8 a) { return rt_copy_bits<__m256>(a); }
RT_FUNC rt_float8 rt_from_avx(__m256 v) { return rt_copy_bits<rt_float8>(v); }
RT_FUNC rt_float8 rt_sub8(rt_float8 a, rt_float8 b) { return rt_from_avx(_mm256_sub_ps(rt_avx(a), rt_avx(b))); }
RT_FUNC rt_float8 rt_mul8(rt_float8 a, rt_float8 b) { return rt_from_avx(_mm256_mul_ps(rt_avx(a), rt_avx(b))); }
RT_FUNC rt_float8 rt_min8(rt_float8 a, rt_float8 b) { return rt_from_avx(_mm256_min_ps(rt_avx(b), rt_avx(a))); }
RT_FUNC rt_float8 rt_max8(rt_float8 a, rt_float8 b) { return rt_from_avx(_mm256_max_ps(rt_avx(b), rt_avx(a))); }
RT_FUNC uint rt_mask_le8(rt_float8 a, rt_float8 b) {
    return uint(_mm256_movemask_ps(_mm256_cmp_ps(rt_avx(a), rt_avx(b), _CMP_LE_OQ)));
}
#else
RT_FUNC rt_float8 rt_sub8(rt_float8 a, rt_float8 b) { return rt_float8{a.lo - b.lo, a.hi - b.hi}; }
RT_FUNC rt_float8 rt_mul8(rt_float8 a, rt_float8 b) { return rt_float8{a.lo * b.lo, a.hi * b.hi}; }
RT_FUNC rt_float8 rt_min8(rt_float8 a, rt_float8 b) { return rt_float8{rt_min4(a.lo, b.lo), rt_min4(a.hi, b.hi)}; }
RT_FUNC rt_float8 rt_max8(rt_float8 a, rt_float8 b) { return rt_float8{rt_max4(a.lo, b.lo), rt_max4(a.hi, b.hi)}; }
RT_FUNC uint rt_mask_le8(rt_float8 a, rt_float8 b) { return rt_mask_le4(a.lo, b.lo) | (rt_mask_le4(a.hi, b.hi) << 4); }
#endif
#if defined(__AVX2__)
// A lane moved to the bottom by a permute, not through a stack slot.
RT_FUNC float rt_lane8(rt_float8 v, uint k) {
    return _mm256_cvtss_f32(_mm256_permutevar8x32_ps(rt_avx(v), _mm256_castsi128_si256(_mm_cvtsi32_si128(int(k)))));
}
// Lane k of the 8-lane uint vector (lo, hi).
RT_FUNC uint rt_lane8_u(uint4 lo, uint4 hi, uint k) {
    __m256i v = _mm256_set_m128i(rt_copy_bits<__m128i>(hi), rt_copy_bits<__m128i>(lo));
    return uint(_mm_cvtsi128_si32(
        _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(v, _mm256_castsi128_si256(_mm_cvtsi32_si128(int(k)))))));
}
#else
RT_FUNC float rt_lane8(rt_float8 v, uint k) {
    float lanes[8];
    std::memcpy(lanes, &v, sizeof lanes);
    return lanes[k];
}
// Lane k of the 8-lane uint vector (lo, hi).
RT_FUNC uint rt_lane8_u(uint4 lo, uint4 hi, uint k) {
    uint lanes[8];
    std::memcpy(lanes, &lo, sizeof lo);
    std::memcpy(lanes + 4, &hi, sizeof hi);
    return lanes[k];
}
#endif
// The index of the lowest set bit of a nonzero x.
RT_FUNC uint rt_lowest_bit(uint x) { return uint(std::countr_zero(x)); }

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
#define RT_GLOBAL_PTR_ro(type) const type*  // an array the stages only read
#define RT_GLOBAL_PTR_rw(type) type*

// Buffers: `kg` is a struct of pointers generated from kernels/data_arrays.h.
#define RT_FETCH(kg, array, i) ((kg).array[(i)])
#define RT_STORE(kg, array, i, value) ((kg).array[(i)] = (value))
#define RT_FETCH_ONCE(kg, array, i) RT_FETCH(kg, array, i)  // no streaming hint: compat/cuda.h and opencl.h have one
#define RT_STORE_ONCE(kg, array, i, value) RT_STORE(kg, array, i, value)
// Atomic add on a uint buffer element, returning the old value. atomic_ref keeps the buffers plain arrays.
#define RT_ATOMIC_ADD(kg, array, i, value) (std::atomic_ref<uint>((kg).array[(i)]).fetch_add((value)))
// n consecutive slots of a queue counter (kernels/stages.h, rt_queue_reserve): one atomic add per item.
#define RT_QUEUE_RESERVE(kg, array, i, n) RT_ATOMIC_ADD(kg, array, i, n)
// Each item is its own group (kernels/stages.h, rt_stage_shade).
#define RT_QUEUE_RESERVE_GROUP(kg, array, i, n) RT_ATOMIC_ADD(kg, array, i, n)
#define RT_GROUP_COUNT(p) ((p) ? 1u : 0u)
#define RT_GROUP_COUNT_BELOW(p) 0u
// A hint that elements [i, i + n) of a device array are needed soon (the wide traversal's pushed children).
#define RT_PREFETCH(kg, array, i, n)                                             \
    do {                                                                         \
        const char* rt_first_ = reinterpret_cast<const char*>(&(kg).array[(i)]); \
        for (size_t rt_o_ = 0; rt_o_ < sizeof((kg).array[0]) * (n); rt_o_ += 64) \
            __builtin_prefetch(rt_first_ + rt_o_);                               \
    } while (0)

// The grid loop of a stage entry. The cpu backend's thread pool runs it on every worker; each takes the next range
// of items from a shared cursor (rt_cpu_grid), so one worker loop serves every stage. Ranges are guided: a share of
// what is left (large at first, so each worker streams through long runs of rays and hits the hardware prefetchers
// follow; a 64-ray chunk each time cost a third of the two-thread query speed), down to `chunk` items at the end,
// so a worker that drew slow rays (glass) does not finish long after the others.
struct RtCpuGrid {
    std::atomic<uint>* next;  // shared cursor for the current launch
    uint chunk;               // the smallest range
    uint workers;
};
// Defined here (an inline variable, zero-initialised) rather than `extern`: every stage build (SSE2, AVX2) then
// reads it directly instead of through a TLS wrapper call, which UBSan also reported as a null access.
inline thread_local RtCpuGrid rt_cpu_grid{};
// Takes [begin, *end) of the n items; begin >= n when none are left.
static inline uint rt_cpu_take(uint n, uint* end) {
    uint begin = rt_cpu_grid.next->load(std::memory_order_relaxed);
    while (begin < n) {
        uint size = rt_max_u(rt_cpu_grid.chunk, (n - begin) / (4u * rt_cpu_grid.workers));
        uint stop = n - begin > size ? begin + size : n;
        if (rt_cpu_grid.next->compare_exchange_weak(begin, stop, std::memory_order_relaxed)) {
            *end = stop;
            return begin;
        }
    }
    return begin;
}
// The same ranges whole, for a stage that walks two of its items at a time (rt_walk_range, kernels/stages.h).
#define RT_GRID_RANGES(begin, end, n) \
    for (uint rt_n_ = (n), end = 0u, begin = rt_cpu_take(rt_n_, &end); begin < rt_n_; begin = rt_cpu_take(rt_n_, &end))
#define RT_GRID_LOOP(i, n)                                                                            \
    for (uint rt_n_ = (n), rt_end_ = 0u, rt_begin_ = rt_cpu_take(rt_n_, &rt_end_); rt_begin_ < rt_n_; \
         rt_begin_ = rt_cpu_take(rt_n_, &rt_end_))                                                    \
        for (uint i = rt_begin_; i < rt_end_; ++i)

#endif
