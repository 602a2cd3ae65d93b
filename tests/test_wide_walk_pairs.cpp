// The cpu backends' traversal stages walk a wide scene's rays two at a time (rt_walk_range, kernels/stages.h): each
// ray's hit must be the one its own walk (rt_trace_wide) finds, bit for bit, whichever walk ends first and whatever
// ray it starts next, for closest and any hits, two-level and flattened instances, and for any ray count (one, two,
// odd). The shadow stage's walks are checked by the cpu backend's frames against cpu-ref's (test_agreement_cpu.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/render/device_scene.h"
#include "core/render/host_globals.h"
#include "core/render/render_engine.h"
#include "kernels/traverse.h"
#include "tests/test_support.h"

namespace {

// Rays of every kind a pair meets: from the camera into the model, the floor and the sky, with short and long
// reaches, and from inside the model outwards, so the two walks of a pair take very different numbers of steps.
std::vector<prism::RayQuery> mixed_rays(const prism::Scene& scene) {
    std::vector<prism::RayQuery> rays;
    const glm::vec3 eye = scene.camera.position;
    const glm::vec3 target = scene.camera.target;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
            glm::vec3 d = glm::normalize(target - eye + glm::vec3(0.06f * float(x - 20), 0.06f * float(y - 26), 0.0f));
            float reach = (x + y) % 3 == 0 ? 0.5f * glm::length(target - eye) : INFINITY;
            rays.push_back(prism::RayQuery{{eye.x, eye.y, eye.z}, 0.0f, {d.x, d.y, d.z}, reach});
            glm::vec3 o = target + glm::vec3(0.01f * float(x - 20), 0.01f * float(y - 20), 0.0f);
            glm::vec3 out = glm::normalize(glm::vec3(std::sin(0.7f * x), std::cos(1.3f * y), std::sin(0.3f * (x + y))));
            rays.push_back(prism::RayQuery{{o.x, o.y, o.z}, 1e-4f, {out.x, out.y, out.z}, INFINITY});
        }
    rays.push_back(rays.front());  // an odd count
    return rays;
}

// As Renderer::trace hands a query to the intersect stage.
Ray to_ray(const prism::RayQuery& q) {
    return Ray{float4{q.origin[0], q.origin[1], q.origin[2], q.tmin},
               float4{q.direction[0], q.direction[1], q.direction[2], q.tmax},
               float4{0, 0, 0, 0},
               0,
               RT_CHANNEL_ALL,
               0,
               0};
}

Hit walk_alone(KernelGlobals kg, const Ray& r, bool any_hit, bool flat) {
    return rt_trace_wide(kg, rt_xyz(r.origin), rt_xyz(r.direction), r.origin.w, r.direction.w, any_hit, false, flat);
}

class WideWalkPairs : public ::testing::TestWithParam<bool> {};  // flattened instances or the two levels

TEST_P(WideWalkPairs, EachRayHitsWhatItsOwnWalkHits) {
    const bool flat = GetParam();
    prism::Scene scene = prism::test::load_test_scene("builtin:bunny");
    prism::BvhBuildOptions options;
    options.layout = prism::BvhLayout::Wide;
    options.flatten_instances = flat;
    const prism::DeviceScene device = prism::build_device_scene(scene, options);
    ASSERT_EQ(device.bvh_options.flatten_instances, flat);
    ASSERT_GT(scene.instances.size(), 1u);  // not a one-instance start
    FrameParams frame{};
    KernelGlobals kg = prism::host_globals(device, &frame);
    const std::vector<prism::RayQuery> all = mixed_rays(scene);
    prism::RenderEngine engine("cpu", device);
    for (size_t count : {size_t(1), size_t(2), all.size()}) {
        const std::vector<prism::RayQuery> queries(all.begin(), all.begin() + long(count));
        for (bool any_hit : {false, true}) {
            SCOPED_TRACE(std::to_string(count) + (any_hit ? " rays, any hit" : " rays, closest hit"));
            std::vector<prism::RayHit> traced = engine.trace(queries, any_hit);
            ASSERT_EQ(traced.size(), queries.size());
            size_t hits = 0;
            for (size_t i = 0; i < queries.size(); ++i) {
                Hit alone = walk_alone(kg, to_ray(queries[i]), any_hit, flat);
                ASSERT_EQ(traced[i].t, alone.tuv.x) << "ray " << i;
                if (!(alone.tuv.x < RT_INFINITY)) continue;
                ++hits;
                ASSERT_EQ(traced[i].instance, alone.instance) << "ray " << i;
                ASSERT_EQ(traced[i].primitive, alone.primitive) << "ray " << i;
                ASSERT_EQ(traced[i].u, alone.tuv.y) << "ray " << i;
                ASSERT_EQ(traced[i].v, alone.tuv.z) << "ray " << i;
            }
            if (count == all.size()) {
                EXPECT_GT(hits, count / 4);
                EXPECT_LT(hits, count - count / 8);  // misses and short reaches too
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Layouts, WideWalkPairs, ::testing::Bool(), [](const ::testing::TestParamInfo<bool>& info) {
    return info.param ? "FlattenedInstances" : "TwoLevels";
});

}  // namespace
