// The two intersection tests of thesis 6.2.3: ray-box (slabs, Algorithm 6-4) and ray-triangle (barycentric,
// eq. 6.2, solved with the Moeller-Trumbore form of Cramer's rule). Conditions are written so NaNs fail them.
#ifndef RT_INTERSECT_H
#define RT_INTERSECT_H

#include "math.h"
#include "types.h"

// Entry distance of the ray into the box, or +inf when it misses [tmin, tmax].
RT_FUNC float rt_intersect_box(float3 lower, float3 upper, float3 origin, float3 inv_dir, float tmin, float tmax) {
    float3 t0 = (lower - origin) * inv_dir;
    float3 t1 = (upper - origin) * inv_dir;
    float3 near3 = rt_min3v(t0, t1);
    float3 far3 = rt_max3v(t0, t1);
    float t_near = rt_max(rt_max(near3.x, near3.y), rt_max(near3.z, tmin));
    float t_far = rt_min(rt_min(far3.x, far3.y), rt_min(far3.z, tmax));
    return t_near <= t_far ? t_near : RT_INFINITY;
}

RT_FUNC float rt_intersect_node(BvhNode node, float3 origin, float3 inv_dir, float tmin, float tmax) {
    return rt_intersect_box(rt_xyz(node.lower), rt_xyz(node.upper), origin, inv_dir, tmin, tmax);
}

// Returns (t, u, v, 1) for a hit with tmin < t < tmax, else (+inf, 0, 0, 0). u and v weight the second and
// third vertex. Two-sided: no culling (glass is seen from both sides).
RT_FUNC float4 rt_intersect_triangle(TriangleGeometry tri, float3 origin, float3 dir, float tmin, float tmax) {
    float4 miss = make_float4(RT_INFINITY, 0.0f, 0.0f, 0.0f);
    float3 e1 = rt_xyz(tri.e1);
    float3 e2 = rt_xyz(tri.e2);
    float3 p = cross(dir, e2);
    float det = dot(e1, p);
    if (det == 0.0f) return miss;
    float inv_det = 1.0f / det;
    float3 s = origin - rt_xyz(tri.v0);
    float u = dot(s, p) * inv_det;
    if (!(u >= 0.0f && u <= 1.0f)) return miss;
    float3 q = cross(s, e1);
    float v = dot(dir, q) * inv_det;
    if (!(v >= 0.0f && u + v <= 1.0f)) return miss;
    float t = dot(e2, q) * inv_det;
    if (!(t > tmin && t < tmax)) return miss;
    return make_float4(t, u, v, 1.0f);
}

#endif
