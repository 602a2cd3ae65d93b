// The intersection tests of kernels/intersect.h compiled as C++ (thesis 6.2.3), with the edge cases that break
// naive implementations: edges and vertices, parallel rays, zero direction components, tmin/tmax, NaN.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "kernels/intersect.h"

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

TriangleGeometry triangle(float3 a, float3 b, float3 c) {
    return TriangleGeometry{float4{a.x, a.y, a.z, 0}, float4{b.x - a.x, b.y - a.y, b.z - a.z, 0},
                            float4{c.x - a.x, c.y - a.y, c.z - a.z, 0}};
}

float box(float3 lower, float3 upper, float3 o, float3 d, float tmin = 0.0f, float tmax = inf) {
    return rt_intersect_box(lower, upper, o, rt_safe_inverse(d), tmin, tmax);
}

const TriangleGeometry unit = triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});

}  // namespace

TEST(RayBox, HitFromOutsideReturnsEntryDistance) {
    EXPECT_FLOAT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0, 0, -5}, {0, 0, 1}), 4.0f);
}

TEST(RayBox, OriginInsideReturnsTmin) {
    EXPECT_FLOAT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0, 0, 0}, {0, 0, 1}, 0.25f), 0.25f);
}

TEST(RayBox, MissesBesideAndBehind) {
    EXPECT_EQ(box({-1, -1, -1}, {1, 1, 1}, {3, 0, -5}, {0, 0, 1}), inf);
    EXPECT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0, 0, 5}, {0, 0, 1}), inf);  // box behind the origin
}

TEST(RayBox, RespectsTmax) {
    EXPECT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0, 0, -5}, {0, 0, 1}, 0.0f, 3.9f), inf);
    EXPECT_FLOAT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0, 0, -5}, {0, 0, 1}, 0.0f, 4.1f), 4.0f);
}

TEST(RayBox, AxisParallelRaysWithZeroComponents) {
    // Zero components would give 0 * inf = NaN in a naive slab test.
    EXPECT_FLOAT_EQ(box({-1, -1, -1}, {1, 1, 1}, {0.5f, 0.5f, -5}, {0, 0, 1}), 4.0f);
    EXPECT_EQ(box({-1, -1, -1}, {1, 1, 1}, {1.5f, 0.5f, -5}, {0, 0, 1}), inf);
    EXPECT_FLOAT_EQ(box({-1, -1, -1}, {1, 1, 1}, {-5, 0, 0}, {1, 0, 0}), 4.0f);
}

TEST(RayBox, FlatBoxOfATriangleInAPlaneIsHit) {
    EXPECT_FLOAT_EQ(box({0, 0, 2}, {1, 1, 2}, {0.5f, 0.5f, 0}, {0, 0, 1}), 2.0f);
}

TEST(RayTriangle, CentreHitGivesBarycentrics) {
    float4 h = rt_intersect_triangle(unit, float3{0.25f, 0.5f, -1}, float3{0, 0, 1}, 0.0f, inf);
    EXPECT_FLOAT_EQ(h.x, 1.0f);
    EXPECT_FLOAT_EQ(h.y, 0.25f);  // weight of the second vertex
    EXPECT_FLOAT_EQ(h.z, 0.5f);   // weight of the third vertex
    EXPECT_EQ(h.w, 1.0f);
}

TEST(RayTriangle, BothSidesAreHit) {
    float4 h = rt_intersect_triangle(unit, float3{0.25f, 0.25f, 1}, float3{0, 0, -1}, 0.0f, inf);
    EXPECT_FLOAT_EQ(h.x, 1.0f);
}

TEST(RayTriangle, EdgesAndVerticesCount) {
    EXPECT_LT(rt_intersect_triangle(unit, float3{0.5f, 0.0f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
    EXPECT_LT(rt_intersect_triangle(unit, float3{0.0f, 0.0f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
    EXPECT_LT(rt_intersect_triangle(unit, float3{0.5f, 0.5f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
}

TEST(RayTriangle, JustOutsideMisses) {
    EXPECT_EQ(rt_intersect_triangle(unit, float3{0.51f, 0.5f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
    EXPECT_EQ(rt_intersect_triangle(unit, float3{-0.01f, 0.5f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
}

TEST(RayTriangle, ParallelRayMisses) {
    EXPECT_EQ(rt_intersect_triangle(unit, float3{-1, 0.25f, 0}, float3{1, 0, 0}, 0.0f, inf).x, inf);
}

TEST(RayTriangle, IntervalIsOpen) {
    EXPECT_EQ(rt_intersect_triangle(unit, float3{0.25f, 0.25f, -1}, float3{0, 0, 1}, 0.0f, 1.0f).x, inf);
    EXPECT_EQ(rt_intersect_triangle(unit, float3{0.25f, 0.25f, -1}, float3{0, 0, 1}, 1.0f, inf).x, inf);
    EXPECT_EQ(rt_intersect_triangle(unit, float3{0.25f, 0.25f, 1}, float3{0, 0, 1}, 0.0f, inf).x, inf);  // behind
}

TEST(RayTriangle, DegenerateTriangleNeverHits) {
    TriangleGeometry line = triangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0});
    EXPECT_EQ(rt_intersect_triangle(line, float3{0.5f, 0, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
}

TEST(RayTriangle, NanRayNeverHits) {
    float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(rt_intersect_triangle(unit, float3{nan, 0.25f, -1}, float3{0, 0, 1}, 0.0f, inf).x, inf);
    EXPECT_EQ(rt_intersect_triangle(unit, float3{0.25f, 0.25f, -1}, float3{0, nan, 1}, 0.0f, inf).x, inf);
}
