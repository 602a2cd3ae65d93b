// Coplanar overlapping triangles (kernels/traverse.h, rt_hit_wins): hits within RT_TIE_EPSILON of each other are
// one distance, and the lower instance, then primitive, wins whatever order the traversal meets them in, so the
// backends, whose float rounding differs, agree on which surface shows (McGuire's conference room was 41 dB
// between cpu-ref and PoCL before this rule).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/render/device_scene.h"
#include "core/render/render_engine.h"
#include "core/scene/seed_material.h"
#include "kernels/traverse.h"
#include "tests/test_support.h"

namespace {

Hit hit_at(float t, uint instance, uint primitive) {
    Hit h = rt_no_hit();
    h.tuv.x = t;
    h.instance = instance;
    h.primitive = primitive;
    return h;
}

TEST(HitTies, TheLowerInstanceThenPrimitiveWinsWithinTheBand) {
    const Hit best = hit_at(10.0f, 1u, 5u);
    const float within = 10.0f * (1.0f + 0.5f * RT_TIE_EPSILON), beyond = 10.0f * (1.0f + 4.0f * RT_TIE_EPSILON);
    EXPECT_TRUE(rt_hit_wins(within, 1u, 4u, best));        // a tie: the lower primitive
    EXPECT_FALSE(rt_hit_wins(within, 1u, 6u, best));       // a tie: the higher primitive loses, though met later
    EXPECT_TRUE(rt_hit_wins(within, 0u, 9u, best));        // a tie: the lower instance first
    EXPECT_FALSE(rt_hit_wins(beyond, 0u, 0u, best));       // farther than the band: never
    EXPECT_TRUE(rt_hit_wins(9.9f, 7u, 7u, best));          // clearly nearer: always
    EXPECT_TRUE(rt_hit_wins(1e30f, 7u, 7u, rt_no_hit()));  // anything beats no hit
    // Reach: the band past the best, never past the ray's tmax.
    EXPECT_FLOAT_EQ(rt_hit_reach(best, INFINITY), 10.0f * (1.0f + RT_TIE_EPSILON));
    EXPECT_EQ(rt_hit_reach(best, 10.0f), 10.0f);
    EXPECT_EQ(rt_hit_reach(rt_no_hit(), 5.0f), 5.0f);
    // A hit in a triangle's edge slack (kernels/intersect.h) lies beyond the band of an exact hit at the same
    // distance, from either side, so the exact one wins whichever the traversal meets first.
    const Hit exact = hit_at(10.0f, 3u, 3u);
    EXPECT_FALSE(rt_hit_wins(10.0f * RT_SLACK_FARTHER, 0u, 0u, exact));
    EXPECT_TRUE(rt_hit_wins(10.0f, 3u, 3u, hit_at(10.0f * RT_SLACK_FARTHER, 0u, 0u)));
}

// Two unit quads in z = 0, one over the other, as primitives 0-1 and 2-3 of one mesh, in two instances of it:
// every ray down the z axis onto them is a four-way tie.
prism::Scene stacked_quads() {
    prism::Scene scene;
    scene.source = "stacked quads";
    prism::Mesh mesh;
    for (int copy = 0; copy < 2; ++copy) {
        uint32_t base = static_cast<uint32_t>(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}});
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
    }
    mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    scene.meshes.push_back(mesh);
    scene.instances.push_back(prism::Instance{0, glm::mat4(1.0f), "first"});
    scene.instances.push_back(prism::Instance{0, glm::mat4(1.0f), "second"});
    scene.materials.push_back(prism::default_material());
    return scene;
}

TEST(HitTies, EveryLayoutAndBackendPicksTheSameSurface) {
    std::vector<prism::RayQuery> rays;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            rays.push_back({{-0.97f + 0.06f * x, -0.97f + 0.06f * y, 5.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY});
    const prism::Scene scene = stacked_quads();
    const std::vector<std::string> backends = {"cpu-ref", "cpu", prism::test::test_device("opencl"),
                                               prism::test::test_device("vulkan")};
    for (prism::BvhLayout layout : {prism::BvhLayout::Stack, prism::BvhLayout::Escape, prism::BvhLayout::Wide}) {
        prism::BvhBuildOptions options;
        options.layout = layout;
        options.max_leaf_size = 1;  // every triangle in a leaf of its own: the order of visits varies most
        const prism::DeviceScene device = prism::build_device_scene(scene, options);
        for (const std::string& backend : backends) {
            std::string reason;
            if (!prism::test::backend_spec_runs_here(backend, &reason)) continue;
            if (layout == prism::BvhLayout::Wide && backend != "cpu-ref" && backend != "cpu") continue;
            SCOPED_TRACE(backend + ", layout " + std::to_string(int(layout)));
            std::vector<prism::RayHit> hits = prism::RenderEngine(backend, device).trace(rays, false);
            ASSERT_EQ(hits.size(), rays.size());
            for (const prism::RayHit& h : hits) {
                ASSERT_NEAR(h.t, 5.0f, 1e-5f);
                ASSERT_EQ(h.instance, 0u);
                ASSERT_LE(h.primitive, 1u);  // the first quad, whose two triangles do not overlap each other
            }
        }
    }
}

}  // namespace
