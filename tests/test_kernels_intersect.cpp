// The intersection tests of kernels/intersect.h compiled as C++ (thesis 6.2.3), with the edge cases that break
// naive implementations: edges and vertices, parallel rays, zero direction components, tmin/tmax, NaN.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "kernels/intersect.h"

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

TriangleGeometry triangle(float3 a, float3 b, float3 c) {
    float3 e1 = b - a, e2 = c - a;
    return TriangleGeometry{float4{a.x, a.y, a.z, 0}, float4{e1.x, e1.y, e1.z, rt_edge_scale(e1, e2)},
                            float4{e2.x, e2.y, e2.z, 0}};
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

// Two triangles sharing the diagonal of a quad 2e-5 across, seen from 800 times that distance (a sphere of
// MetalRoughSpheresNoTextures): without the edge slack of kernels/intersect.h one ray in fifteen aimed at the shared
// edge fell outside both, and the scalar and four-lane tests must agree ray for ray.
TEST(RayTriangle, DistantRaysThroughASharedEdgeNeverFallBetween) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> unit_interval(0.0f, 1.0f);
    int leaks = 0;
    for (int k = 0; k < 20000; ++k) {
        const float size = 2e-5f;
        float3 corner{0.01f + 0.001f * unit_interval(rng), 0.006f + 0.001f * unit_interval(rng), -0.003f};
        float3 ex{size, 0.3f * size * unit_interval(rng), 0.2f * size};
        float3 ey{0.1f * size * unit_interval(rng), size, 0.5f * size * unit_interval(rng)};
        float3 far_corner = corner + ex + ey;
        TriangleGeometry first = triangle(corner, corner + ex, far_corner);
        TriangleGeometry second = triangle(corner, far_corner, corner + ey);
        float3 on_edge = corner + (far_corner - corner) * unit_interval(rng);
        float3 origin{0.0123f, 0.0084f, 0.008f + 0.01f * unit_interval(rng)};
        float3 dir = normalize(on_edge - origin);
        bool hit_first = rt_intersect_triangle(first, origin, dir, 0.0f, inf).x < inf;
        bool hit_second = rt_intersect_triangle(second, origin, dir, 0.0f, inf).x < inf;
        leaks += !hit_first && !hit_second;

        TriangleBlock block{};
        const TriangleGeometry* lanes[2] = {&first, &second};
        for (int lane = 0; lane < 2; ++lane) {
            const TriangleGeometry& t = *lanes[lane];
            (&block.v0x.x)[lane] = t.v0.x, (&block.v0y.x)[lane] = t.v0.y, (&block.v0z.x)[lane] = t.v0.z;
            (&block.e1x.x)[lane] = t.e1.x, (&block.e1y.x)[lane] = t.e1.y, (&block.e1z.x)[lane] = t.e1.z;
            (&block.e2x.x)[lane] = t.e2.x, (&block.e2y.x)[lane] = t.e2.y, (&block.e2z.x)[lane] = t.e2.z;
        }
        TriangleHits4 four = rt_intersect_triangles4(block, origin, dir, 0.0f, inf);
        ASSERT_EQ(four.mask, (hit_first ? 1u : 0u) | (hit_second ? 2u : 0u)) << "ray " << k;
    }
    EXPECT_EQ(leaks, 0);
}

// From far away the slack is wide: a ray just outside the triangle's edge still hits it, at a distance reported
// RT_SLACK_FARTHER times longer, so a neighbour the ray truly crosses wins the tie rule (tests/test_hit_ties.cpp).
TEST(RayTriangle, SlackHitsReportALongerDistance) {
    float4 inside = rt_intersect_triangle(unit, float3{2e-4f, 0.25f, -1000}, float3{0, 0, 1}, 0.0f, inf);
    float4 outside = rt_intersect_triangle(unit, float3{-2e-4f, 0.25f, -1000}, float3{0, 0, 1}, 0.0f, inf);
    EXPECT_EQ(inside.x, 1000.0f);
    EXPECT_EQ(outside.x, 1000.0f * RT_SLACK_FARTHER);
    EXPECT_EQ(rt_intersect_triangle(unit, float3{-0.1f, 0.25f, -1000}, float3{0, 0, 1}, 0.0f, inf).x, inf);
}
