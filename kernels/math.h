// Small vector helpers every stage uses, in the shared subset of C++/CUDA/OpenCL C/GLSL (no swizzles, no
// overloading, no out-parameters).
#ifndef RT_MATH_H
#define RT_MATH_H

#include "compat/compat.h"

#define RT_PI 3.14159265358979f
#define RT_NONE 0xffffffffu
#define RT_FLT_MAX 3.402823466e+38f

RT_FUNC float3 rt_xyz(float4 v) { return make_float3(v.x, v.y, v.z); }
RT_FUNC float4 rt_float4(float3 v, float w) { return make_float4(v.x, v.y, v.z, w); }
RT_FUNC float3 rt_splat3(float s) { return make_float3(s, s, s); }
RT_FUNC float4 rt_splat4(float s) { return make_float4(s, s, s, s); }
RT_FUNC float rt_max3(float3 v) { return rt_max(v.x, rt_max(v.y, v.z)); }
RT_FUNC float rt_clamp01(float x) { return rt_min(rt_max(x, 0.0f), 1.0f); }
RT_FUNC float3 rt_lerp3(float3 a, float3 b, float t) { return a * (1.0f - t) + b * t; }
RT_FUNC float3 rt_min3v(float3 a, float3 b) {
    return make_float3(rt_min(a.x, b.x), rt_min(a.y, b.y), rt_min(a.z, b.z));
}
RT_FUNC float3 rt_max3v(float3 a, float3 b) {
    return make_float3(rt_max(a.x, b.x), rt_max(a.y, b.y), rt_max(a.z, b.z));
}

// Selects channel c (0, 1, 2) of v; GLSL has v[c] but C++/CUDA/OpenCL vectors do not.
RT_FUNC float rt_channel(float3 v, uint c) { return c == 0u ? v.x : (c == 1u ? v.y : v.z); }
// Keeps only the channels in mask (bit 0 = red): the weight of a single-wavelength ray after dispersion.
RT_FUNC float3 rt_mask3(float3 v, uint mask) {
    return make_float3((mask & 1u) != 0u ? v.x : 0.0f, (mask & 2u) != 0u ? v.y : 0.0f, (mask & 4u) != 0u ? v.z : 0.0f);
}

// Affine 3x4 transform given as three rows (the Instance matrices).
RT_FUNC float3 rt_transform_point(float4 r0, float4 r1, float4 r2, float3 p) {
    return make_float3(dot(rt_xyz(r0), p) + r0.w, dot(rt_xyz(r1), p) + r1.w, dot(rt_xyz(r2), p) + r2.w);
}
RT_FUNC float3 rt_transform_vector(float4 r0, float4 r1, float4 r2, float3 v) {
    return make_float3(dot(rt_xyz(r0), v), dot(rt_xyz(r1), v), dot(rt_xyz(r2), v));
}
// Normals transform by the inverse transpose: with the world-to-object rows that is the transpose product.
RT_FUNC float3 rt_transform_normal(float4 w2o0, float4 w2o1, float4 w2o2, float3 n) {
    return rt_xyz(w2o0) * n.x + rt_xyz(w2o1) * n.y + rt_xyz(w2o2) * n.z;
}

// 1/d with zero components replaced by a tiny value of the same sign, so slab tests never compute 0 * inf.
// Schlick's Fresnel reflectance from the normal-incidence reflectance f0, at cos_theta to the normal.
RT_FUNC float rt_schlick(float f0, float cos_theta) {
    float x = 1.0f - cos_theta;
    float x2 = x * x;
    return f0 + (1.0f - f0) * (x2 * x2 * x);
}

// Normal-incidence reflectance between media of IORs a and b.
RT_FUNC float rt_ior_to_f0(float a, float b) {
    float r = (a - b) / (a + b);
    return r * r;
}

RT_FUNC float rt_safe_inverse1(float x) {
    float tiny = 1e-20f;
    return 1.0f / (rt_abs(x) > tiny ? x : (x >= 0.0f ? tiny : -tiny));
}
RT_FUNC float3 rt_safe_inverse(float3 d) {
    return make_float3(rt_safe_inverse1(d.x), rt_safe_inverse1(d.y), rt_safe_inverse1(d.z));
}

// Moves a surface point off the surface along n by a few ulps (Waechter & Binder, Ray Tracing Gems ch. 6):
// robust at any distance from the origin, so secondary rays start at t = 0 without self-intersection.
RT_FUNC float rt_offset_component(float p, float n) {
    float origin = 1.0f / 32.0f;
    float float_scale = 1.0f / 65536.0f;
    int of = rt_int(256.0f * n);
    float p_int = rt_int_as_float(rt_as_int(p) + (p < 0.0f ? -of : of));
    return rt_abs(p) < origin ? p + float_scale * n : p_int;
}
RT_FUNC float3 rt_offset_ray_origin(float3 p, float3 n) {
    return make_float3(rt_offset_component(p.x, n.x), rt_offset_component(p.y, n.y), rt_offset_component(p.z, n.z));
}

// Thesis eq. 6.9 (n faces the incoming ray).
RT_FUNC float3 rt_reflect(float3 d, float3 n) { return d - n * (2.0f * dot(d, n)); }

// Thesis eq. 6.30: refraction of unit d through unit n (facing the incoming ray), eta = eta1 / eta2. Returns the
// direction in xyz and w = 1, or w = 0 on total internal reflection.
RT_FUNC float4 rt_refract(float3 d, float3 n, float eta) {
    float cos1 = -dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cos1 * cos1);
    if (k < 0.0f) return make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    return rt_float4(d * eta + n * (eta * cos1 - rt_sqrt(k)), 1.0f);
}

#endif
