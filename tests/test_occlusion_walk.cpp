// The shadow stage's speculative walk (kernels/traverse.h, rt_trace_occlusion): a ray that finds a leaf puts it
// aside and walks on from its stack, inside the instance it is in. Whatever the order it tests leaves in, a ray is
// blocked exactly when the plain any-hit walk and the closest-hit walk say something lies in its range, also where
// it enters and leaves instances (a leaf put aside must be tested before the walk leaves its instance).
#include <gtest/gtest.h>

#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "core/render/device_scene.h"
#include "core/render/host_globals.h"
#include "core/scene/seed_material.h"
#include "kernels/traverse.h"

namespace {

// Small random triangles in a unit cube, in three instances: one as built, one turned and scaled, one moved away.
prism::Scene triangle_cloud(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    prism::Scene scene;
    scene.source = "triangle cloud";
    prism::Mesh mesh;
    for (uint32_t i = 0; i < 3000; ++i) {
        glm::vec3 centre{unit(rng), unit(rng), unit(rng)};
        for (int corner = 0; corner < 3; ++corner)
            mesh.positions.push_back(centre + 0.06f * glm::vec3{unit(rng), unit(rng), unit(rng)});
        mesh.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    scene.meshes.push_back(mesh);
    scene.instances.push_back(prism::Instance{0, glm::mat4(1.0f), "as built"});
    glm::mat4 turned = glm::rotate(glm::translate(glm::mat4(1.0f), {0.5f, 0.2f, -0.3f}), 0.7f, {0.3f, 1.0f, 0.2f});
    scene.instances.push_back(prism::Instance{0, glm::scale(turned, glm::vec3(0.8f)), "turned"});
    scene.instances.push_back(prism::Instance{0, glm::translate(glm::mat4(1.0f), {2.5f, 0.0f, 0.0f}), "moved"});
    scene.materials.push_back(prism::default_material());
    return scene;
}

TEST(OcclusionWalk, BlockedExactlyWhereTheOtherWalksFindAHit) {
    const prism::DeviceScene device = prism::build_device_scene(triangle_cloud(7));  // the stack layout
    ASSERT_EQ(device.bvh_options.layout, prism::BvhLayout::Stack);
    FrameParams frame{};
    frame.bvh_layout = RT_BVH_LAYOUT_STACK;
    const KernelGlobals kg = prism::host_globals(device, &frame);

    std::mt19937 rng(11);
    std::uniform_real_distribution<float> box(-2.0f, 4.0f), unit(-1.0f, 1.0f), length(0.05f, 6.0f);
    int blocked = 0, open = 0;
    for (int i = 0; i < 20000; ++i) {
        float3 origin{box(rng), 0.6f * box(rng), 0.6f * box(rng)};
        glm::vec3 d = glm::normalize(glm::vec3{unit(rng), unit(rng), unit(rng)} + glm::vec3(1e-3f));
        float3 direction{d.x, d.y, d.z};
        float tmax = i % 4 == 0 ? RT_INFINITY : length(rng);  // shadow rays to point and directional lights
        Hit speculative = rt_trace_occlusion(kg, origin, direction, 0.0f, tmax);
        Hit any = rt_trace(kg, origin, direction, 0.0f, tmax, true);
        Hit closest = rt_trace(kg, origin, direction, 0.0f, tmax, false);
        bool is_blocked = speculative.tuv.x < RT_INFINITY;
        ASSERT_EQ(is_blocked, any.tuv.x < RT_INFINITY) << "ray " << i;
        ASSERT_EQ(is_blocked, closest.tuv.x < RT_INFINITY) << "ray " << i;
        if (is_blocked) {
            // The hit it reports is a real one, in range, and no nearer than the closest.
            EXPECT_LE(speculative.tuv.x, tmax) << "ray " << i;
            EXPECT_GE(speculative.tuv.x, closest.tuv.x) << "ray " << i;
            EXPECT_LT(speculative.instance, 3u) << "ray " << i;
        }
        (is_blocked ? blocked : open) += 1;
    }
    // Both kinds are common, so both paths of the walk were taken.
    EXPECT_GT(blocked, 2000);
    EXPECT_GT(open, 2000);
}

}  // namespace
