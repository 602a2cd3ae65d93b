// bench::coherent_order (bench/query_rays.h), the order `prism rays --bench --ray-order coherent` traces in: a
// permutation that groups rays by direction octant, then by origin along a Morton curve, and keeps the order of
// rays that share a key.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "bench/query_rays.h"

namespace {

prism::RayQuery ray(float ox, float oy, float oz, float dx, float dy, float dz) {
    return prism::RayQuery{{ox, oy, oz}, 0.0f, {dx, dy, dz}, std::numeric_limits<float>::infinity()};
}

uint32_t octant(const prism::RayQuery& r) {
    return (r.direction[0] < 0.0f ? 1u : 0u) | (r.direction[1] < 0.0f ? 2u : 0u) | (r.direction[2] < 0.0f ? 4u : 0u);
}

TEST(CoherentRayOrder, IsAPermutationGroupedByOctant) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::vector<prism::RayQuery> rays;
    for (int i = 0; i < 5000; ++i)
        rays.push_back(ray(unit(rng), unit(rng), unit(rng), unit(rng), unit(rng), unit(rng)));
    std::vector<size_t> order = prism::bench::coherent_order(rays);
    ASSERT_EQ(order.size(), rays.size());
    std::vector<size_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "not a permutation";
    for (size_t i = 1; i < order.size(); ++i)
        EXPECT_LE(octant(rays[order[i - 1]]), octant(rays[order[i]])) << "octants interleave at " << i;
}

TEST(CoherentRayOrder, OrdersOriginsAlongTheCurveAndKeepsTies) {
    // One octant. Origins at the box's corners: (0,0,0) first, (1,1,1) last on the Morton curve; the two rays
    // from (0,0,0) keep their order (a stable sort).
    std::vector<prism::RayQuery> rays = {ray(1, 1, 1, 1, 1, 1), ray(0, 0, 0, 1, 1, 1), ray(1, 0, 0, 1, 1, 1),
                                         ray(0, 0, 0, 1, 2, 1)};
    std::vector<size_t> order = prism::bench::coherent_order(rays);
    EXPECT_EQ(order, (std::vector<size_t>{1, 3, 2, 0}));
}

TEST(TwoPointRayOrder, GroupsRaysThatGoTheSameWayAndKeepsTies) {
    // From one origin, rays to +x and to -x alternate; the order puts each direction's rays together, in their
    // order. From two origins far apart, rays group by origin.
    std::vector<prism::RayQuery> rays = {ray(0, 0, 0, 1, 0, 0), ray(0, 0, 0, -1, 0, 0), ray(0, 0, 0, 1, 0, 0),
                                         ray(0, 0, 0, -1, 0, 0)};
    std::vector<size_t> order = prism::bench::two_point_order(rays);
    EXPECT_EQ(order, (std::vector<size_t>{1, 3, 0, 2}));
    std::vector<prism::RayQuery> apart = {ray(0, 0, 0, 0, 0, 1), ray(100, 100, 100, 0, 0, 1), ray(0, 0, 0, 0, 0, 1),
                                          ray(100, 100, 100, 0, 0, 1)};
    EXPECT_EQ(prism::bench::two_point_order(apart), (std::vector<size_t>{0, 2, 1, 3}));
}

// A ray file may hold NaN or infinite coordinates: both orders still return a permutation (UBSan checks the
// conversions in the sanitizer build).
TEST(CoherentRayOrder, NonFiniteRaysStillGetAnOrder) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<prism::RayQuery> rays = {ray(nan, 0, 0, 1, 0, 0), ray(0, inf, 0, 0, 1, 0), ray(1, 1, 1, nan, 0, 1),
                                         ray(-inf, 2, 2, 0, 0, -1)};
    for (const std::vector<size_t>& order : {prism::bench::coherent_order(rays), prism::bench::two_point_order(rays)}) {
        std::vector<size_t> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        EXPECT_EQ(sorted, (std::vector<size_t>{0, 1, 2, 3}));
    }
}

}  // namespace
