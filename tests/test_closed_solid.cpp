// Closed solids (core/scene/closed_solid.h, RT_INSTANCE_CLOSED_SOLID): which meshes count as one, and the shade
// stage's rule that a point inside one sees no light outside its bounds. The rule is checked against what it
// replaces: every shadow ray it leaves out, traced in a scene built without the rule, is blocked.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/render/device_scene.h"
#include "core/render/host_globals.h"
#include "core/render/render_engine.h"
#include "core/scene/closed_solid.h"
#include "core/scene/procedural.h"
#include "core/scene/seed_material.h"
#include "kernels/stages.h"
#include "tests/test_support.h"

namespace {

// A unit cube, counter-clockwise seen from outside. `split_faces`: each face with its own four vertices (as glTF
// stores a cube with per-face normals), so only the positions say that the faces meet.
prism::Mesh cube(glm::vec3 lower = glm::vec3(0.0f), float size = 1.0f, bool split_faces = false) {
    prism::Mesh mesh;
    mesh.name = "cube";
    const glm::ivec4 faces[6] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    auto corner = [&](int i) { return lower + size * glm::vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1); };
    if (!split_faces)
        for (int i = 0; i < 8; ++i) mesh.positions.push_back(corner(i));
    for (const glm::ivec4& f : faces) {
        glm::uvec4 v(f);
        if (split_faces) {
            uint32_t base = uint32_t(mesh.positions.size());
            for (int k = 0; k < 4; ++k) mesh.positions.push_back(corner(f[k]));
            v = glm::uvec4(base, base + 1, base + 2, base + 3);
        }
        mesh.triangles.push_back({v.x, v.y, v.z});
        mesh.triangles.push_back({v.x, v.z, v.w});
    }
    mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    return mesh;
}

prism::Mesh reversed(prism::Mesh mesh) {
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    return mesh;
}

prism::Mesh merged(prism::Mesh a, const prism::Mesh& b) {
    uint32_t base = uint32_t(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    for (glm::uvec3 t : b.triangles) a.triangles.push_back(t + glm::uvec3(base));
    a.triangle_materials.assign(a.triangles.size(), 0);
    return a;
}

TEST(ClosedSolid, ClosedOutwardMeshesAreSolids) {
    EXPECT_TRUE(prism::is_closed_solid(cube()));
    EXPECT_TRUE(prism::is_closed_solid(cube(glm::vec3(0.0f), 1.0f, true)));  // seams welded by position
    EXPECT_TRUE(prism::is_closed_solid(merged(cube(), cube(glm::vec3(3.0f)))));
    // The builtin scenes' spheres: their seam and poles share exact positions.
    EXPECT_TRUE(prism::is_closed_solid(prism::make_uv_sphere(24, 48)));
    EXPECT_TRUE(prism::is_closed_solid(prism::make_uv_sphere(50, 100)));
    // A triangle whose corners fall on two positions is left out; the rest still closes.
    prism::Mesh with_sliver = cube();
    with_sliver.triangles.push_back({0, 0, 1});
    EXPECT_TRUE(prism::is_closed_solid(with_sliver));
}

TEST(ClosedSolid, OpenInsideOutAndFlatMeshesAreNot) {
    prism::Mesh open = cube();
    open.triangles.pop_back();
    EXPECT_FALSE(prism::is_closed_solid(open));
    EXPECT_FALSE(prism::is_closed_solid(reversed(cube())));                                 // normals inwards
    EXPECT_FALSE(prism::is_closed_solid(merged(cube(), reversed(cube(glm::vec3(3.0f))))));  // one piece inside out
    prism::Mesh crossed = cube();  // one face wound the other way: its edges run the same way as their neighbours'
    std::swap(crossed.triangles[0].y, crossed.triangles[0].z);
    std::swap(crossed.triangles[1].y, crossed.triangles[1].z);
    EXPECT_FALSE(prism::is_closed_solid(crossed));
    prism::Mesh fin = cube();  // a third triangle on an edge: not a manifold
    fin.positions.push_back({0.5f, -1.0f, 0.0f});
    fin.triangles.push_back({0, 1, 8});
    EXPECT_FALSE(prism::is_closed_solid(fin));
    // A double-sided sheet: every edge has two triangles wound opposite ways, and no volume.
    prism::Mesh sheet;
    sheet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
    EXPECT_FALSE(prism::is_closed_solid(sheet));
    // The same far from the origin, its back wound from another corner: the volume is summed about the sheet itself,
    // so the rounding of products of coordinates near 1e5 does not pass for a volume.
    prism::Mesh far_sheet;
    far_sheet.positions = {
        {1e5f, -2e5f, 3e5f}, {1e5f + 1.3f, -2e5f + 0.2f, 3e5f}, {1e5f + 0.1f, -2e5f + 1.7f, 3e5f + 0.4f}};
    far_sheet.triangles = {{0, 1, 2}, {1, 0, 2}};
    EXPECT_FALSE(prism::is_closed_solid(far_sheet));
    EXPECT_TRUE(prism::is_closed_solid(cube(glm::vec3(1e5f, -2e5f, 3e5f), 2.0f)));  // a solid there still is one
    prism::Mesh bad = cube();
    bad.positions[3].x = NAN;
    EXPECT_FALSE(prism::is_closed_solid(bad));
    bad = cube();
    bad.triangles[0].x = 8;  // out of range
    EXPECT_FALSE(prism::is_closed_solid(bad));
    EXPECT_FALSE(prism::is_closed_solid(prism::Mesh{}));
}

TEST(ClosedSolid, AFanOfManyTrianglesAtOneVertexIsCheckedInLinearTime) {
    // A hostile file's shape: 200,000 triangles around one vertex (an open disc). The vertex's edge list is sorted
    // and searched, not scanned once per edge (which would take 4e10 steps).
    prism::Mesh fan;
    const uint32_t n = 200000;
    fan.positions.push_back(glm::vec3(0.0f));
    for (uint32_t i = 0; i < n; ++i) {
        float a = 6.2831853f * float(i) / float(n);
        fan.positions.push_back({std::cos(a), std::sin(a), 0.0f});
    }
    for (uint32_t i = 0; i < n; ++i) fan.triangles.push_back({0, 1 + i, 1 + (i + 1) % n});
    EXPECT_FALSE(prism::is_closed_solid(fan));
}

prism::Material glass() {
    prism::Material m = prism::default_material();
    m.transmittance = 0.9f;
    m.reflectivity = 0.3f;
    m.ior = glm::vec3(1.5f);
    prism::set_dielectric_fresnel(m, prism::schlick_f0(1.5f));
    return m;
}

// A glass cube over a floor, lit by a point light at `lamp` and the sun.
prism::Scene glass_cube_scene(glm::vec3 lamp) {
    prism::Scene scene;
    scene.source = "glass cube";
    scene.materials = {prism::default_material(), glass()};
    scene.meshes.push_back(prism::make_ground_plane(10.0f));
    prism::Mesh box = cube(glm::vec3(-1.0f, 0.2f, -1.0f), 2.0f, true);
    box.triangle_materials.assign(box.triangles.size(), 1);
    scene.meshes.push_back(box);
    scene.instances.push_back(prism::Instance{0, glm::mat4(1.0f), "floor"});
    scene.instances.push_back(prism::Instance{1, glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0, 1, 0)), "box"});
    prism::Light point;
    point.type = prism::LightType::Point;
    point.position = lamp;
    point.intensity = 4.0f;
    prism::Light sun;
    sun.type = prism::LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.2f));
    scene.lights = {point, sun};
    scene.ambient_light = glm::vec3(0.1f);
    scene.camera.position = {0.5f, 3.0f, 5.0f};
    scene.camera.target = {0.0f, 1.0f, 0.0f};
    scene.has_camera = true;
    return scene;
}

prism::BvhBuildOptions with_solids(bool on) {
    prism::BvhBuildOptions options;
    options.closed_solids = on;
    return options;
}

TEST(ClosedSolid, InstancesAreMarkedOnlyWhenTheRuleHolds) {
    prism::Scene scene = glass_cube_scene({3.0f, 4.0f, 2.0f});
    prism::DeviceScene device = prism::build_device_scene(scene);
    EXPECT_EQ(device.closed_solid_instances, 1u);
    EXPECT_EQ(device.instances[0].flags & RT_INSTANCE_CLOSED_SOLID, 0u);  // the floor is open
    EXPECT_NE(device.instances[1].flags & RT_INSTANCE_CLOSED_SOLID, 0u);
    EXPECT_EQ(device.instances[1].solid_upper.y, 2.2f);  // the mesh's bounds, in object space
    EXPECT_EQ(prism::build_device_scene(scene, with_solids(false)).closed_solid_instances, 0u);
    // Moving the instance keeps its mark and bounds.
    prism::update_instance_transforms(device, {glm::mat4(1.0f), glm::mat4(1.0f)}, false);
    EXPECT_NE(device.instances[1].flags & RT_INSTANCE_CLOSED_SOLID, 0u);
    EXPECT_EQ(device.instances[1].solid_lower.x, -1.0f);

    prism::Scene blended = scene;  // light passes a blended surface in the shadow_layers stage
    blended.materials[1].alpha_mode = prism::AlphaMode::Blend;
    EXPECT_EQ(prism::build_device_scene(blended).closed_solid_instances, 0u);
    prism::Scene opaque = scene;  // no ray gets inside: nothing to gain, and the mesh is not examined
    opaque.materials[1].transmittance = 0.0f;
    EXPECT_EQ(prism::build_device_scene(opaque).closed_solid_instances, 0u);
    prism::Scene overridden = scene;  // the instance's own material decides
    overridden.instances[1].material_override = 0;
    EXPECT_EQ(prism::build_device_scene(overridden).closed_solid_instances, 0u);
    prism::Scene open = scene;
    open.meshes[1].triangles.pop_back();
    open.meshes[1].triangle_materials.pop_back();
    EXPECT_EQ(prism::build_device_scene(open).closed_solid_instances, 0u);
}

// Follows every camera ray of a small frame through its reflections and refractions (depth 6) in two builds of one
// scene, with and without closed solids; at every hit compares the shadow rays each build asks for. Returns how many
// the rule left out; every one of them, traced in the build without the rule, must be blocked.
struct RuleCheck {
    int left_out = 0;
    int left_out_unblocked = 0;
    int traced_only_with_rule = 0;
};

RuleCheck check_rule(const prism::Scene& scene) {
    prism::DeviceScene with = prism::build_device_scene(scene, with_solids(true));
    prism::DeviceScene without = prism::build_device_scene(scene, with_solids(false));
    EXPECT_GT(with.closed_solid_instances, 0u);
    FrameParams frame{};
    frame.ambient_light = float4{0.1f, 0.1f, 0.1f, 0.0f};
    frame.min_weight = 1e-4f;
    frame.width = frame.height = 1;
    frame.max_depth = 6;
    frame.light_count = uint32_t(scene.lights.size());
    KernelGlobals kg_with = prism::host_globals(with, &frame);
    KernelGlobals kg_without = prism::host_globals(without, &frame);
    RuleCheck check;
    const int size = 48;
    glm::vec3 eye = scene.camera.position;
    glm::vec3 forward = glm::normalize(scene.camera.target - eye);
    glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
    glm::vec3 up = glm::cross(right, forward);
    std::vector<Ray> rays;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            glm::vec3 d = glm::normalize(forward + right * (0.8f * (2.0f * (x + 0.5f) / size - 1.0f)) +
                                         up * (0.8f * (1.0f - 2.0f * (y + 0.5f) / size)));
            rays.push_back(
                rt_make_ray(float3{eye.x, eye.y, eye.z}, float3{d.x, d.y, d.z}, float3{1, 1, 1}, 0, RT_CHANNEL_ALL, 0));
        }
    while (!rays.empty()) {
        Ray ray = rays.back();
        rays.pop_back();
        Hit hit = rt_trace(kg_with, rt_xyz(ray.origin), rt_xyz(ray.direction), 0.0f, RT_INFINITY, false);
        if (!(hit.tuv.x < RT_INFINITY)) continue;
        Ray children[RT_MAX_CHILDREN];
        ShadeResult shade = rt_shade(kg_with, ray, hit, children);
        ShadeResult plain = rt_shade(kg_without, ray, hit, children);
        for (uint32_t l = 0; l < frame.light_count; ++l) {
            ShadowRay ruled = rt_shadow_ray(kg_with, shade.lit, l, 0u);
            ShadowRay traced = rt_shadow_ray(kg_without, plain.lit, l, 0u);
            if (ruled.contribution.w != 0.0f && traced.contribution.w == 0.0f) ++check.traced_only_with_rule;
            if (ruled.contribution.w != 0.0f || traced.contribution.w == 0.0f) continue;
            ++check.left_out;
            Hit blocker =
                rt_trace(kg_without, rt_xyz(traced.origin), rt_xyz(traced.direction), 0.0f, traced.direction.w, true);
            check.left_out_unblocked += !(blocker.tuv.x < RT_INFINITY);
        }
        for (uint32_t c = 0; c < shade.child_count; ++c) rays.push_back(children[c]);
    }
    return check;
}

TEST(ClosedSolid, EveryShadowRayTheRuleLeavesOutIsBlocked) {
    // The lamp outside the cube: rays inside the glass see neither light.
    RuleCheck outside = check_rule(glass_cube_scene({3.0f, 4.0f, 2.0f}));
    EXPECT_GT(outside.left_out, 100);
    EXPECT_EQ(outside.left_out_unblocked, 0);
    EXPECT_EQ(outside.traced_only_with_rule, 0);
    // The lamp inside the cube (a bulb in its glass): only the sun's rays are left out; the lamp's are traced.
    RuleCheck inside = check_rule(glass_cube_scene({0.2f, 1.0f, 0.1f}));
    EXPECT_GT(inside.left_out, 50);
    EXPECT_EQ(inside.left_out_unblocked, 0);
    EXPECT_EQ(inside.traced_only_with_rule, 0);
    // A real scene: the builtin sphere scene's glass sphere (a UV sphere of 9,800 triangles).
    RuleCheck sphere = check_rule(prism::test::load_test_scene("builtin:sphere"));
    EXPECT_GT(sphere.left_out, 100);
    EXPECT_EQ(sphere.left_out_unblocked, 0);
}

TEST(ClosedSolid, LampInsideTheSolidStillLightsItsInside) {
    // Shading a point inside the cube: the lamp inside gets a shadow ray, the sun outside none.
    prism::Scene scene = glass_cube_scene({0.2f, 1.0f, 0.1f});
    prism::DeviceScene device = prism::build_device_scene(scene);
    FrameParams frame{};
    frame.min_weight = 1e-4f;
    frame.max_depth = 2;
    frame.light_count = 2;
    KernelGlobals kg = prism::host_globals(device, &frame);
    // From inside the cube towards its floor face (y = 0.2), which the lamp above lights.
    Ray ray = rt_make_ray(float3{0.0f, 1.0f, 0.0f}, float3{0.0f, -1.0f, 0.0f}, float3{1, 1, 1}, 0, RT_CHANNEL_ALL, 1);
    Hit hit = rt_trace(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), 0.0f, RT_INFINITY, false);
    ASSERT_EQ(hit.instance, 1u);
    Ray children[RT_MAX_CHILDREN];
    ShadeResult shade = rt_shade(kg, ray, hit, children);
    EXPECT_EQ(shade.lit.solid, 1u);
    EXPECT_NE(rt_shadow_ray(kg, shade.lit, 0u, 0u).contribution.w, 0.0f);  // the lamp
    EXPECT_EQ(rt_shadow_ray(kg, shade.lit, 1u, 0u).contribution.w, 0.0f);  // the sun, behind the glass
}

TEST(ClosedSolid, FramesAreUnchangedWithFewerShadowRays) {
    for (const char* spec : {"builtin:sphere", "glass cube"}) {
        SCOPED_TRACE(spec);
        prism::Scene scene = std::string(spec) == "glass cube" ? glass_cube_scene({0.2f, 1.0f, 0.1f})
                                                               : prism::test::load_test_scene(spec);
        prism::DeviceScene with = prism::build_device_scene(scene, with_solids(true));
        prism::DeviceScene without = prism::build_device_scene(scene, with_solids(false));
        prism::RenderSettings settings = prism::test::small_settings(96, 72, 8);
        prism::FrameResult ruled = prism::RenderEngine("cpu", with).render(scene.camera, settings);
        prism::FrameResult traced = prism::RenderEngine("cpu", without).render(scene.camera, settings);
        EXPECT_EQ(ruled.image, traced.image);
        EXPECT_EQ(ruled.stats.rays_per_depth, traced.stats.rays_per_depth);
        uint64_t shadow_ruled = 0, shadow_traced = 0;
        for (uint32_t n : ruled.stats.shadow_rays_per_depth) shadow_ruled += n;
        for (uint32_t n : traced.stats.shadow_rays_per_depth) shadow_traced += n;
        EXPECT_LT(shadow_ruled, shadow_traced);
    }
}

}  // namespace
