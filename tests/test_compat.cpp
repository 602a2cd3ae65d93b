// The compat layer itself, compiled as C++: each helper against its plain meaning (LuxCore's untested CUDA shim
// shipped a vstore4 bug; ours is tested). The same helpers compile in CUDA/OpenCL/GLSL through the backends.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/accumulate.h"

TEST(Compat, BitCastsRoundTrip) {
    EXPECT_EQ(rt_as_uint(1.0f), 0x3f800000u);
    EXPECT_EQ(rt_as_float(0x40000000u), 2.0f);
    EXPECT_EQ(rt_as_int(-2.0f), static_cast<int>(0xc0000000u));
    EXPECT_EQ(rt_int_as_float(0x3f800000), 1.0f);
    EXPECT_EQ(rt_as_uint(rt_as_float(7u)), 7u);  // small integers survive as denormal bit patterns
}

TEST(Compat, VectorHelpers) {
    float3 a{1, 2, 3}, b{4, 5, 6};
    EXPECT_EQ(dot(a, b), 32.0f);
    float3 c = cross(a, b);
    EXPECT_EQ(c.x, -3.0f);
    EXPECT_EQ(c.y, 6.0f);
    EXPECT_EQ(c.z, -3.0f);
    EXPECT_FLOAT_EQ(length(normalize(a)), 1.0f);
    EXPECT_EQ(rt_max3(a), 3.0f);
    EXPECT_EQ(rt_channel(a, 1), 2.0f);
    float3 m = rt_mask3(a, 5u);
    EXPECT_EQ(m.x, 1.0f);
    EXPECT_EQ(m.y, 0.0f);
    EXPECT_EQ(m.z, 3.0f);
    float3 x = rt_xyz(float4{1, 2, 3, 4});
    EXPECT_EQ(x.z, 3.0f);
    EXPECT_EQ(rt_min_u(3u, 5u), 3u);
    EXPECT_EQ(rt_max_i(-3, 5), 5);
}

TEST(Compat, TransformsUseRows) {
    float4 r0{1, 0, 0, 10}, r1{0, 2, 0, 20}, r2{0, 0, 3, 30};
    float3 p = rt_transform_point(r0, r1, r2, float3{1, 1, 1});
    EXPECT_EQ(p.x, 11.0f);
    EXPECT_EQ(p.y, 22.0f);
    EXPECT_EQ(p.z, 33.0f);
    float3 v = rt_transform_vector(r0, r1, r2, float3{1, 1, 1});
    EXPECT_EQ(v.y, 2.0f);
}

TEST(Compat, SafeInverseHasNoInfinities) {
    float3 inv = rt_safe_inverse(float3{0.0f, -0.0f, 2.0f});
    EXPECT_TRUE(std::isfinite(inv.x));
    EXPECT_GT(inv.x, 0.0f);
    EXPECT_TRUE(std::isfinite(inv.y));
    EXPECT_EQ(inv.z, 0.5f);
}

TEST(Compat, OffsetMovesAlongTheNormalAtAnyScale) {
    for (float scale : {0.001f, 1.0f, 1000.0f, 1e6f}) {
        float3 p{scale, -scale, scale};
        float3 up{0, 0, 1};
        float3 moved = rt_offset_ray_origin(p, up);
        EXPECT_GT(moved.z, p.z) << scale;
        EXPECT_EQ(moved.x, p.x) << scale;
        EXPECT_LT(moved.z - p.z, 1e-3f * std::max(1.0f, scale)) << scale;
    }
}

TEST(Compat, AtomicAddReturnsThePreviousValue) {
    std::vector<uint> counters{5u};
    struct {
        uint* counters;
    } kg{counters.data()};
    EXPECT_EQ(RT_ATOMIC_ADD(kg, counters, 0, 3u), 5u);
    EXPECT_EQ(counters[0], 8u);
}

// Fixed-point accumulation: exact, order-independent, with carries into the high word.
TEST(Compat, AccumulationIsExactAndOrderIndependent) {
    std::vector<uint> forward(6, 0u), backward(6, 0u);
    KernelGlobals kg_forward{}, kg_backward{};
    kg_forward.accum = forward.data();
    kg_backward.accum = backward.data();
    std::vector<float> values;
    for (int i = 0; i < 1000; ++i) values.push_back(0.001f * float(i % 97) + 1e-7f * float(i));
    values.push_back(300.0f);  // crosses 256: exercises the high word
    values.push_back(255.99f);
    for (float v : values) rt_accumulate(kg_forward, 0, float3{v, v * 0.5f, 0.0f});
    for (auto it = values.rbegin(); it != values.rend(); ++it)
        rt_accumulate(kg_backward, 0, float3{*it, *it * 0.5f, 0.0f});
    EXPECT_EQ(forward, backward);
    double expected = 0.0;
    for (float v : values) expected += v;
    EXPECT_NEAR(rt_accumulated(kg_forward, 0).x, expected, expected * 1e-6);
    EXPECT_EQ(rt_accumulated(kg_forward, 0).z, 0.0f);
    rt_accumulate(kg_forward, 0, float3{std::numeric_limits<float>::quiet_NaN(), -1.0f, 0.0f});  // ignored
    EXPECT_NEAR(rt_accumulated(kg_forward, 0).x, expected, expected * 1e-6);
}
