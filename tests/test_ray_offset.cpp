// Secondary and shadow rays start off their own surface (kernels/shade.h, Ray Tracing Gems ch. 6): no shadow ray
// from a lit, unoccluded surface may hit anything, however far the primary ray travelled, so no backend shows
// black speckles and all of them agree where the surface lies.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/render/device_scene.h"
#include "core/render/host_globals.h"
#include "core/scene/seed_material.h"
#include "kernels/stages.h"

namespace {

// A large floor made of a grid of triangles (in the plane y = 0, or tilted and moved far from the origin by its
// instance), seen from far away at a low angle, lit by one directional light from above: nothing can block it.
struct Floor {
    prism::DeviceScene device;
    FrameParams frame{};
    KernelGlobals kg{};

    explicit Floor(const glm::mat4& transform, float half_size) {
        prism::Scene scene;
        scene.source = "floor";
        prism::Mesh mesh;
        const int n = 16;
        for (int z = 0; z <= n; ++z)
            for (int x = 0; x <= n; ++x)
                mesh.positions.push_back({half_size * (2.0f * x / n - 1.0f), 0.0f, half_size * (2.0f * z / n - 1.0f)});
        for (int z = 0; z < n; ++z)
            for (int x = 0; x < n; ++x) {
                uint32_t i = z * (n + 1) + x;
                mesh.triangles.push_back({i, i + n + 1, i + 1});
                mesh.triangles.push_back({i + 1, i + n + 1, i + n + 2});
            }
        mesh.triangle_materials.assign(mesh.triangles.size(), 0);
        scene.meshes.push_back(mesh);
        scene.instances.push_back(prism::Instance{0, transform, "floor"});
        scene.materials.push_back(prism::default_material());
        prism::Light sun;
        sun.type = prism::LightType::Directional;
        sun.direction = glm::vec3(transform * glm::vec4(0.3f, -1.0f, 0.2f, 0.0f));
        scene.lights.push_back(sun);
        device = prism::build_device_scene(scene);
        frame.ambient_light = float4{0.1f, 0.1f, 0.1f, 0.0f};
        frame.min_weight = 1e-4f;
        frame.width = frame.height = 1;
        frame.max_depth = 8;
        frame.light_count = 1;
        kg = prism::host_globals(device, &frame);
    }

    // Shoots a fan of rays from `eye` (in the floor's object space) over the floor; counts the hits and the shadow
    // rays that were blocked.
    std::pair<int, int> blocked_shadow_rays(const glm::mat4& transform, glm::vec3 eye, float half_size) {
        int hits = 0, blocked = 0;
        glm::vec3 world_eye = glm::vec3(transform * glm::vec4(eye, 1.0f));
        for (int i = 0; i < 200; ++i)
            for (int j = 0; j < 200; ++j) {
                glm::vec3 target{half_size * (0.99f * (2.0f * i / 199.0f - 1.0f)) + 0.0137f * j, 0.0f,
                                 half_size * (0.99f * (2.0f * j / 199.0f - 1.0f)) - 0.0071f * i};
                glm::vec3 world_target = glm::vec3(transform * glm::vec4(target, 1.0f));
                glm::vec3 d = glm::normalize(world_target - world_eye);
                Ray ray = rt_make_ray(float3{world_eye.x, world_eye.y, world_eye.z}, float3{d.x, d.y, d.z},
                                      float3{1, 1, 1}, 0, RT_CHANNEL_ALL, 0);
                Hit hit = rt_trace(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), 0.0f, RT_INFINITY, false);
                if (!(hit.tuv.x < RT_INFINITY)) continue;
                ++hits;
                Ray children[RT_MAX_CHILDREN];
                ShadeResult shade = rt_shade(kg, ray, hit, children);
                ShadowRay shadow = rt_shadow_ray(kg, shade.lit, 0u, 0u);
                if (shadow.contribution.w == 0.0f) continue;
                Hit occluder =
                    rt_trace(kg, rt_xyz(shadow.origin), rt_xyz(shadow.direction), 0.0f, shadow.direction.w, true);
                blocked += occluder.tuv.x < RT_INFINITY;
            }
        return {hits, blocked};
    }
};

}  // namespace

// Seen from high above, the hit point o + t d carries an error of a few ulps of the eye's height, far more than
// the fixed offset Ray Tracing Gems gives coordinates near 0 (the floor's y); the barycentric hit point is exact.
TEST(RayOffset, FloorThroughTheOriginCastsNoShadowOnItself) {
    const float half_size = 400.0f;
    Floor floor(glm::mat4(1.0f), half_size);
    auto [hits, blocked] = floor.blocked_shadow_rays(glm::mat4(1.0f), {0.0f, 2000.0f, half_size * 1.5f}, half_size);
    EXPECT_GT(hits, 10000);
    EXPECT_EQ(blocked, 0);
}

TEST(RayOffset, TiltedFloorFarFromTheOriginCastsNoShadowOnItself) {
    const float half_size = 50.0f;
    glm::mat4 transform = glm::translate(glm::mat4(1.0f), glm::vec3(3000.0f, -700.0f, 1200.0f)) *
                          glm::rotate(glm::mat4(1.0f), 0.4f, glm::normalize(glm::vec3(1.0f, 0.2f, 0.5f)));
    Floor floor(transform, half_size);
    auto [hits, blocked] = floor.blocked_shadow_rays(transform, {0.0f, 500.0f, half_size * 1.6f}, half_size);
    EXPECT_GT(hits, 10000);
    EXPECT_EQ(blocked, 0);
}
