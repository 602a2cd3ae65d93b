// Four floats with the operations the BVH builder's inner loops need (box growth, centroids, bin positions):
// SSE2 where the compiler targets it (every x86-64), four scalar lanes elsewhere. Both give the same results:
// each operation is one IEEE operation per lane, and min/max pick like SSE's (the second operand unless the first
// is strictly smaller/larger). Internal to core/bvh.
#pragma once

#include <cstdint>
#include <limits>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define PRISM_BVH_SSE2 1
#else
#define PRISM_BVH_SSE2 0
#endif

namespace prism::bvh_simd {

#if PRISM_BVH_SSE2

struct Float4 {
    __m128 v;
};
inline Float4 load(const float* aligned) { return {_mm_load_ps(aligned)}; }
inline void store(float* aligned, Float4 a) { _mm_store_ps(aligned, a.v); }
inline Float4 splat(float x) { return {_mm_set1_ps(x)}; }
inline Float4 set(float x, float y, float z, float w) { return {_mm_setr_ps(x, y, z, w)}; }
inline Float4 min(Float4 a, Float4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline Float4 max(Float4 a, Float4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline Float4 operator+(Float4 a, Float4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline Float4 operator-(Float4 a, Float4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline Float4 operator*(Float4 a, Float4 b) { return {_mm_mul_ps(a.v, b.v)}; }
// The x, y and z lanes, w cleared (bits kept in w must not reach arithmetic: as floats they may be denormal).
inline Float4 xyz(Float4 a) { return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)))}; }
// Truncates each lane to an integer; lanes must lie in [0, 2^31).
inline void truncate(Float4 a, int32_t (&out)[4]) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(a.v));
}

#else

struct Float4 {
    float v[4];
};
inline Float4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline void store(float* p, Float4 a) {
    for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline Float4 splat(float x) { return {{x, x, x, x}}; }
inline Float4 set(float x, float y, float z, float w) { return {{x, y, z, w}}; }
template <class Op>
Float4 lanewise(Float4 a, Float4 b, Op op) {
    return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
}
inline Float4 min(Float4 a, Float4 b) {
    return lanewise(a, b, [](float x, float y) { return x < y ? x : y; });
}
inline Float4 max(Float4 a, Float4 b) {
    return lanewise(a, b, [](float x, float y) { return x > y ? x : y; });
}
inline Float4 operator+(Float4 a, Float4 b) {
    return lanewise(a, b, [](float x, float y) { return x + y; });
}
inline Float4 operator-(Float4 a, Float4 b) {
    return lanewise(a, b, [](float x, float y) { return x - y; });
}
inline Float4 operator*(Float4 a, Float4 b) {
    return lanewise(a, b, [](float x, float y) { return x * y; });
}
inline Float4 xyz(Float4 a) { return {{a.v[0], a.v[1], a.v[2], 0.0f}}; }
inline void truncate(Float4 a, int32_t (&out)[4]) {
    for (int i = 0; i < 4; ++i) out[i] = int32_t(a.v[i]);
}

#endif

struct alignas(16) Lanes {
    float v[4];
};
inline Lanes lanes(Float4 a) {
    Lanes out;
    store(out.v, a);
    return out;
}

// A box as two Float4 (the fourth lane is carried along and ignored).
struct Box4 {
    Float4 lower = splat(std::numeric_limits<float>::infinity());
    Float4 upper = splat(-std::numeric_limits<float>::infinity());
    void grow(Float4 lo, Float4 hi) {
        lower = min(lower, lo);
        upper = max(upper, hi);
    }
    void grow(const Box4& other) { grow(other.lower, other.upper); }
    void grow(Float4 point) { grow(point, point); }
    // Half the surface area of a non-empty box (its x, y and z lanes).
    float half_area() const {
        Lanes d = lanes(upper - lower);
        return d.v[0] * d.v[1] + d.v[1] * d.v[2] + d.v[2] * d.v[0];
    }
};

}  // namespace prism::bvh_simd
