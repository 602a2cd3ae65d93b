// The seed's three test scenes (thesis chapter 7): sizes, materials, textures and environments as the thesis
// describes them, and a clear error when the Stanford models are not where --data-dir says.
#include <set>

#include <gtest/gtest.h>

#include "core/loaders/builtin_scenes.h"
#include "core/util/error.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace prism {
namespace {

LoadOptions with_data() {
    LoadOptions options;
    options.data_dir = test::scenes_dir();
    return options;
}

const Instance& instance_named(const Scene& scene, const std::string& name) {
    for (const Instance& instance : scene.instances)
        if (instance.name == name) return instance;
    throw std::runtime_error("no instance " + name);
}

glm::vec3 world(const Scene& scene, const Instance& instance, uint32_t vertex) {
    return glm::vec3(instance.transform * glm::vec4(scene.meshes[instance.mesh].positions[vertex], 1.0f));
}

// What every seed scene has: a textured floor, a reflective and a refractive material, lights, a camera.
void expect_seed_ingredients(const Scene& scene) {
    const Instance& floor = instance_named(scene, "floor");
    const Mesh& plane = scene.meshes[floor.mesh];
    EXPECT_EQ(plane.triangles.size(), 2u);
    const Material& floor_material = scene.materials[plane.triangle_materials[0]];
    ASSERT_EQ(floor_material.textures.size(), 1u);
    EXPECT_EQ(floor_material.textures[0].mode, TextureMode::Modulate);
    const Texture& checker = scene.textures[floor_material.textures[0].texture];
    EXPECT_EQ(checker.texels.size(), size_t(checker.width) * checker.height);
    std::set<uint32_t> first_row(checker.texels.begin(), checker.texels.begin() + checker.width);
    EXPECT_EQ(first_row.size(), 2u);  // a checkerboard: two colours
    bool reflective = false, refractive = false;
    for (const Material& material : scene.materials) {
        reflective |= material.reflectivity > 0.0f && material.transmittance == 0.0f;
        refractive |= material.transmittance > 0.0f && material.fresnel_bias < 1.0f;
    }
    EXPECT_TRUE(reflective);
    EXPECT_TRUE(refractive);
    EXPECT_TRUE(scene.has_camera);
    EXPECT_GE(scene.lights.size(), 2u);
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::CubeMap);
    ASSERT_EQ(scene.environment.textures.size(), 6u);
    for (uint32_t face : scene.environment.textures) {
        const Texture& texture = scene.textures.at(face);
        EXPECT_GT(texture.width, 0);
        EXPECT_EQ(texture.width, texture.height);
    }
}

TEST(BuiltinScenes, SphereIsTheSeedGlassSphere) {
    Scene scene = load_scene("builtin:sphere");
    EXPECT_EQ(scene.source, "builtin:sphere");
    expect_seed_ingredients(scene);
    const Instance& sphere = instance_named(scene, "glass sphere");
    const Mesh& mesh = scene.meshes[sphere.mesh];
    EXPECT_GE(mesh.triangles.size(), 9000u);
    EXPECT_LE(mesh.triangles.size(), 11000u);
    EXPECT_EQ(scene.triangle_count(), mesh.triangles.size() + 2);
    ASSERT_EQ(mesh.colors.size(), mesh.positions.size());
    EXPECT_NE(mesh.colors.front(), mesh.colors.back());  // a gradient, not one colour
    const Material& glass = scene.materials[mesh.triangle_materials[0]];
    EXPECT_TRUE(glass.use_vertex_colors);
    EXPECT_EQ(glass.transmittance, 0.9f);
    EXPECT_EQ(glass.reflectivity, 0.3f);
    EXPECT_LT(glass.ior.x, glass.ior.z);  // dispersive
    EXPECT_NEAR(glass.fresnel_bias, std::pow((glass.ior.y - 1) / (glass.ior.y + 1), 2.0f), 1e-6f);
    EXPECT_NEAR(glass.fresnel_scale, 1.0f - glass.fresnel_bias, 1e-6f);
    // Every triangle faces outward and the sphere rests on the floor (y = 0).
    glm::vec3 centre = glm::vec3(sphere.transform[3]);
    float lowest = 1e9f;
    for (const glm::uvec3& t : mesh.triangles) {
        glm::vec3 a = world(scene, sphere, t.x), b = world(scene, sphere, t.y), c = world(scene, sphere, t.z);
        ASSERT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre), 0.0f);
        lowest = std::min({lowest, a.y, b.y, c.y});
    }
    EXPECT_NEAR(lowest, 0.0f, 1e-5f);
    // The camera sees the sphere: it lies in front of the camera.
    EXPECT_GT(glm::dot(centre - scene.camera.position, scene.camera.target - scene.camera.position), 0.0f);
}

TEST(BuiltinScenes, BunnyStandsOnTheFloorAndReflects) {
    Scene scene = load_scene("builtin:bunny", with_data());
    expect_seed_ingredients(scene);
    const Instance& bunny = instance_named(scene, "bunny");
    EXPECT_EQ(scene.meshes[bunny.mesh].triangles.size(), 69451u);
    EXPECT_NEAR(scene.materials[scene.meshes[bunny.mesh].triangle_materials[0]].reflectivity, 0.6f, 1e-6f);
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::CubeMap);
    EXPECT_EQ(scene.textures[scene.environment.textures[0]].width, 1024);  // the Miramar faces, not the fallback
    float lowest = 1e9f;
    for (uint32_t v = 0; v < scene.meshes[bunny.mesh].positions.size(); ++v)
        lowest = std::min(lowest, world(scene, bunny, v).y);
    EXPECT_NEAR(lowest, 0.0f, 1e-4f);
    EXPECT_GT(scene.triangle_count(), 69451u + 2u);  // plus the floor and the glass sphere
}

TEST(BuiltinScenes, DragonIsDispersiveGlass) {
    Scene scene = load_scene("builtin:dragon", with_data());
    expect_seed_ingredients(scene);
    const Instance& dragon = instance_named(scene, "dragon");
    EXPECT_EQ(scene.meshes[dragon.mesh].triangles.size(), 871414u);
    const Material& glass = scene.materials[scene.meshes[dragon.mesh].triangle_materials[0]];
    EXPECT_GT(glass.transmittance, 0.0f);
    EXPECT_LT(glass.ior.x, glass.ior.z);
    EXPECT_GT(scene.triangle_count(), 871414u + 2u);
}

TEST(BuiltinScenes, MissingDataDirectoryIsAClearError) {
    LoadOptions options;
    options.data_dir = test::temp_dir("empty_data_dir");
    for (const char* name : {"builtin:bunny", "builtin:dragon"}) {
        SCOPED_TRACE(name);
        try {
            load_scene(name, options);
            ADD_FAILURE() << "no error";
        } catch (const Error& error) {
            std::string message = error.what();
            EXPECT_EQ(message.rfind((options.data_dir / "stanford").string(), 0), 0u) << message;
            EXPECT_NE(message.find("--data-dir"), std::string::npos) << message;
        }
    }
}

TEST(BuiltinScenes, UnknownNameListsTheKnownOnes) {
    try {
        load_scene("builtin:teapot");
        ADD_FAILURE() << "no error";
    } catch (const Error& error) {
        EXPECT_EQ(std::string(error.what()), "builtin:teapot: unknown built-in scene (known: sphere, bunny, dragon)");
    }
    EXPECT_EQ(builtin_scene_names().size(), 3u);
}

}  // namespace
}  // namespace prism
