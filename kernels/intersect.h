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

// The eight children of a wide node at once: rt_intersect_box lane by lane, the same arithmetic, so a box the
// binary layouts enter is entered here. min/max order each axis' two distances without a branch: picking the
// near plane by the direction's sign costs a mispredicted branch per axis whenever consecutive rays point in
// different octants (diffuse rays: 5% slower overall). An unused lane (a box at +inf on every axis) gets an
// entry distance of +inf or an exit of -inf; tmax must be finite (at most RT_FLT_MAX), so an entry at +inf is a
// miss, as in the stack layout. Mask bit k: child k is entered within [tmin, tmax]; lane k of t: its entry.
RT_STRUCT_BEGIN(WideBoxHits)
    rt_float8 t;
    uint mask;
RT_STRUCT_END(WideBoxHits)

RT_FUNC WideBoxHits rt_intersect_wide_node(BvhWideNode node, float3 origin, float3 inv_dir, float tmin, float tmax) {
    rt_float8 ox = rt_splat8(origin.x);
    rt_float8 oy = rt_splat8(origin.y);
    rt_float8 oz = rt_splat8(origin.z);
    rt_float8 ix = rt_splat8(inv_dir.x);
    rt_float8 iy = rt_splat8(inv_dir.y);
    rt_float8 iz = rt_splat8(inv_dir.z);
    rt_float8 x0 = rt_mul8(rt_sub8(rt_make8(node.lower_x0, node.lower_x1), ox), ix);
    rt_float8 x1 = rt_mul8(rt_sub8(rt_make8(node.upper_x0, node.upper_x1), ox), ix);
    rt_float8 y0 = rt_mul8(rt_sub8(rt_make8(node.lower_y0, node.lower_y1), oy), iy);
    rt_float8 y1 = rt_mul8(rt_sub8(rt_make8(node.upper_y0, node.upper_y1), oy), iy);
    rt_float8 z0 = rt_mul8(rt_sub8(rt_make8(node.lower_z0, node.lower_z1), oz), iz);
    rt_float8 z1 = rt_mul8(rt_sub8(rt_make8(node.upper_z0, node.upper_z1), oz), iz);
    rt_float8 near_x = rt_min8(x0, x1), far_x = rt_max8(x0, x1);
    rt_float8 near_y = rt_min8(y0, y1), far_y = rt_max8(y0, y1);
    rt_float8 near_z = rt_min8(z0, z1), far_z = rt_max8(z0, z1);
    WideBoxHits hits;
    hits.t = rt_max8(rt_max8(near_x, near_y), rt_max8(near_z, rt_splat8(tmin)));
    rt_float8 t_far = rt_min8(rt_min8(far_x, far_y), rt_min8(far_z, rt_splat8(tmax)));
    hits.mask = rt_mask_le8(hits.t, t_far);
    return hits;
}

// Moeller-Trumbore's u and v are dot products of s = origin - v0 with vectors the size of the triangle, so their
// rounding error grows with |s| / |edge|: a ray from far away through the edge two triangles share can fall
// outside both and leak through a closed mesh (a dark speck where it then meets the far side from inside). Each
// of u and v is a triple product of s, the direction and an edge, whose rounding error is a few units of
// roundoff times the product of the three vectors' largest components; the tests accept barycentrics down to minus
// four units of that scale (2^-22), so neighbours overlap by a sliver instead of leaving a crack (docs/kernels.md,
// "Edges", has the margin measured). A hit in that sliver reports its distance RT_SLACK_FARTHER times longer,
// beyond the tie band of traverse.h (RT_TIE_EPSILON), so the triangle the ray truly crosses wins whenever it is
// found too: the slack only fills cracks, and elsewhere the hits stay those of a watertight test (Embree's).
#define RT_EDGE_SLACK (1.0f / 4194304.0f)
#define RT_SLACK_FARTHER 1.00004f

RT_FUNC float rt_max_abs3(float3 a) { return rt_max(rt_max(rt_abs(a.x), rt_abs(a.y)), rt_abs(a.z)); }
// The edges' share of the bound, stored in TriangleGeometry.e1.w when the scene is built: the scalar test then
// spends no registers or instructions on it (the four-lane test computes it, having no spare lane).
RT_FUNC float rt_edge_scale(float3 e1, float3 e2) { return rt_max_abs3(e1) + rt_max_abs3(e2); }

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
    float slack = RT_EDGE_SLACK * rt_max_abs3(s) * rt_max_abs3(dir) * tri.e1.w * rt_abs(inv_det);
    float u = dot(s, p) * inv_det;
    if (!(u >= -slack && u <= 1.0f + slack)) return miss;
    float3 q = cross(s, e1);
    float v = dot(dir, q) * inv_det;
    if (!(v >= -slack && u + v <= 1.0f + slack)) return miss;
    float t = dot(e2, q) * inv_det;
    if (!(u >= 0.0f && v >= 0.0f && u + v <= 1.0f)) t = t * RT_SLACK_FARTHER;
    if (!(t > tmin && t < tmax)) return miss;
    return make_float4(t, u, v, 1.0f);
}

RT_STRUCT_BEGIN(TriangleHits4)
    float4 t;        // lane k: the distance if bit k of `exact` is set...
    float4 t_slack;  // ...else this one, RT_SLACK_FARTHER times longer (rt_lane_distance picks)
    float4 u;
    float4 v;
    uint mask;   // bit k: triangle k is hit with tmin < t < tmax
    uint exact;  // bit k: triangle k is hit inside its edges, not in the slack
RT_STRUCT_END(TriangleHits4)

// Lane k's distance as rt_intersect_triangle reports it.
RT_FUNC float rt_lane_distance(TriangleHits4 hits, uint k) {
    return (hits.exact & (1u << k)) != 0u ? rt_lane(hits.t, k) : rt_lane(hits.t_slack, k);
}

// The four triangles of a block at once: rt_intersect_triangle lane by lane, the same operations in the same
// order, so each lane's t, u, v and verdict are the scalar test's (no FMA contraction on the cpu backend).
RT_FUNC TriangleHits4 rt_intersect_triangles4(TriangleBlock tri, float3 origin, float3 dir, float tmin, float tmax) {
    float4 dx = rt_splat4(dir.x);
    float4 dy = rt_splat4(dir.y);
    float4 dz = rt_splat4(dir.z);
    float4 zero = rt_splat4(0.0f);
    float4 one = rt_splat4(1.0f);
    // p = cross(dir, e2), det = dot(e1, p)
    float4 px = dy * tri.e2z - dz * tri.e2y;
    float4 py = dz * tri.e2x - dx * tri.e2z;
    float4 pz = dx * tri.e2y - dy * tri.e2x;
    float4 det = tri.e1x * px + tri.e1y * py + tri.e1z * pz;
    float4 inv_det = one / det;
    // s = origin - v0, u = dot(s, p) / det
    float4 sx = rt_splat4(origin.x) - tri.v0x;
    float4 sy = rt_splat4(origin.y) - tri.v0y;
    float4 sz = rt_splat4(origin.z) - tri.v0z;
    float4 s_max = rt_max4(rt_max4(rt_abs4(sx), rt_abs4(sy)), rt_abs4(sz));
    float4 e1_max = rt_max4(rt_max4(rt_abs4(tri.e1x), rt_abs4(tri.e1y)), rt_abs4(tri.e1z));
    float4 e2_max = rt_max4(rt_max4(rt_abs4(tri.e2x), rt_abs4(tri.e2y)), rt_abs4(tri.e2z));
    float4 edge_scale = e1_max + e2_max;  // rt_edge_scale lane by lane
    float4 slack = rt_splat4(RT_EDGE_SLACK) * s_max * rt_splat4(rt_max_abs3(dir)) * edge_scale * rt_abs4(inv_det);
    TriangleHits4 hits;
    hits.u = (sx * px + sy * py + sz * pz) * inv_det;
    // q = cross(s, e1), v = dot(dir, q) / det, t = dot(e2, q) / det
    float4 qx = sy * tri.e1z - sz * tri.e1y;
    float4 qy = sz * tri.e1x - sx * tri.e1z;
    float4 qz = sx * tri.e1y - sy * tri.e1x;
    hits.v = (dx * qx + dy * qy + dz * qz) * inv_det;
    float4 low = zero - slack;
    float4 high = one + slack;
    hits.t = (tri.e2x * qx + tri.e2y * qy + tri.e2z * qz) * inv_det;
    hits.t_slack = hits.t * rt_splat4(RT_SLACK_FARTHER);
    float4 uv = hits.u + hits.v;
    // The verdicts combine as lane masks (vector registers on the cpu backend) and become bits twice, not once per
    // comparison (docs/kernels.md, "The wide layout", has the gain).
    rt_lanes4 nonzero = rt_or_lanes4(rt_lt_lanes4(det, zero), rt_lt_lanes4(zero, det));
    rt_lanes4 inside = rt_and_lanes4(rt_and_lanes4(rt_le_lanes4(low, hits.u), rt_le_lanes4(hits.u, high)),
                                     rt_and_lanes4(rt_le_lanes4(low, hits.v), rt_le_lanes4(uv, high)));
    rt_lanes4 exact =
        rt_and_lanes4(rt_and_lanes4(rt_le_lanes4(zero, hits.u), rt_le_lanes4(zero, hits.v)), rt_le_lanes4(uv, one));
    rt_lanes4 in_range = rt_and_lanes4(rt_lt_lanes4(rt_splat4(tmin), hits.t), rt_lt_lanes4(hits.t, rt_splat4(tmax)));
    rt_lanes4 in_range_slack =
        rt_and_lanes4(rt_lt_lanes4(rt_splat4(tmin), hits.t_slack), rt_lt_lanes4(hits.t_slack, rt_splat4(tmax)));
    hits.exact = rt_lane_bits4(exact);
    hits.mask = rt_lane_bits4(
        rt_and_lanes4(rt_and_lanes4(nonzero, inside),
                      rt_or_lanes4(rt_and_lanes4(exact, in_range), rt_andnot_lanes4(exact, in_range_slack))));
    return hits;
}

#endif
