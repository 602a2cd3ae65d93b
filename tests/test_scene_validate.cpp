// validate_scene: each broken reference or non-finite value is reported with the source, mesh and element.
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "core/loaders/load_obj.h"
#include "core/loaders/load_ply.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using test::error_message;

// A valid two-triangle scene the tests break one thing at a time.
Scene quad_scene() {
    Scene scene;
    scene.source = "quad.json";
    Mesh mesh;
    mesh.name = "quad";
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.normals.assign(4, glm::vec3(0, 0, 1));
    mesh.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.colors.assign(4, glm::vec4(1.0f));
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.triangle_materials = {0, 1};
    scene.meshes.push_back(mesh);
    scene.materials.resize(2);
    Texture texture;
    texture.width = 2;
    texture.height = 1;
    texture.texels = {0u, 0u};
    scene.textures.push_back(texture);
    scene.materials[1].textures.push_back(TextureLayer{});
    scene.instances.push_back(Instance{});
    return scene;
}

std::string validation_error(const Scene& scene) {
    return error_message([&] { validate_scene(scene); });
}

TEST(SceneValidate, AcceptsAValidScene) { EXPECT_NO_THROW(validate_scene(quad_scene())); }

TEST(SceneValidate, DegenerateTrianglesAreAllowed) {
    Scene scene = quad_scene();
    scene.meshes[0].triangles.push_back({1, 1, 1});
    scene.meshes[0].triangle_materials.push_back(0);
    EXPECT_NO_THROW(validate_scene(scene));
}

TEST(SceneValidate, IndexOutOfRange) {
    Scene scene = quad_scene();
    scene.meshes[0].triangles[1].z = 4;
    EXPECT_EQ(validation_error(scene),
              "quad.json: mesh 0 'quad': triangle 1 references vertex 4 but there are 4 vertices");
}

TEST(SceneValidate, NonFiniteVertexData) {
    Scene scene = quad_scene();
    scene.meshes[0].positions[2].y = NAN;
    EXPECT_EQ(validation_error(scene).rfind("quad.json: mesh 0 'quad': vertex 2 has a non-finite position (1, ", 0), 0u)
        << validation_error(scene);
    scene = quad_scene();
    scene.meshes[0].normals[3].x = INFINITY;
    EXPECT_NE(validation_error(scene).find("vertex 3 has a non-finite normal"), std::string::npos);
    scene = quad_scene();
    scene.meshes[0].uv0[0].y = NAN;
    EXPECT_NE(validation_error(scene).find("vertex 0 has a non-finite TEXCOORD_0"), std::string::npos);
    scene = quad_scene();
    scene.meshes[0].colors[1].w = -INFINITY;
    EXPECT_NE(validation_error(scene).find("vertex 1 has a non-finite colour"), std::string::npos);
}

TEST(SceneValidate, AttributeArraysMatchPositions) {
    Scene scene = quad_scene();
    scene.meshes[0].uv1.resize(3);
    EXPECT_EQ(validation_error(scene), "quad.json: mesh 0 'quad': 3 TEXCOORD_1 for 4 vertices");
}

TEST(SceneValidate, MaterialReferences) {
    Scene scene = quad_scene();
    scene.meshes[0].triangle_materials.pop_back();
    EXPECT_EQ(validation_error(scene), "quad.json: mesh 0 'quad': 1 triangle materials for 2 triangles");
    scene = quad_scene();
    scene.meshes[0].triangle_materials[1] = 2;
    EXPECT_EQ(validation_error(scene),
              "quad.json: mesh 0 'quad': triangle 1 uses material 2 but there are 2 materials");
    scene = quad_scene();
    scene.materials[1].name = "brick";
    scene.materials[1].textures[0].texture = 1;
    EXPECT_EQ(validation_error(scene),
              "quad.json: material 1 'brick': texture layer 0 uses texture 1 but there are 1 textures");
}

TEST(SceneValidate, TexturesAndEnvironment) {
    Scene scene = quad_scene();
    scene.textures[0].texels.pop_back();
    EXPECT_EQ(validation_error(scene), "quad.json: texture 0: 1 texels for 2x1");
    scene = quad_scene();
    scene.environment.kind = EnvironmentKind::Equirect;
    scene.environment.textures = {3};
    EXPECT_EQ(validation_error(scene), "quad.json: environment texture 0 is texture 3 but there are 1 textures");
    scene.environment.kind = EnvironmentKind::CubeMap;
    scene.environment.textures = {0, 0, 0};
    EXPECT_EQ(validation_error(scene), "quad.json: environment needs 6 texture(s) but has 3");
}

TEST(SceneValidate, Instances) {
    Scene scene = quad_scene();
    scene.instances.push_back(Instance{3, glm::mat4(1.0f), "copy"});
    EXPECT_EQ(validation_error(scene), "quad.json: instance 1 'copy' uses mesh 3 but there are 1 meshes");
    scene = quad_scene();
    scene.instances[0].transform[3][1] = NAN;
    EXPECT_EQ(validation_error(scene), "quad.json: instance 0 has a non-finite transform");
}

// A light the shade stage could not use (non-finite numbers, negative light, a cone glTF's bounds exclude) is
// refused in one line; the loosened bounds exporters need (equal angles, pi/2 rounded up) pass.
TEST(SceneValidate, Lights) {
    auto with = [](const std::function<void(Light&)>& edit) {
        Scene scene = quad_scene();
        Light light;
        light.type = LightType::Spot;
        light.position = {0, 2, 0};
        edit(light);
        scene.lights = {Light{}, light};
        return scene;
    };
    EXPECT_NO_THROW(validate_scene(with([](Light&) {})));
    EXPECT_NO_THROW(validate_scene(with([](Light& l) { l.inner_cone = l.outer_cone = 0.3f; })));
    EXPECT_NO_THROW(validate_scene(with([](Light& l) { l.outer_cone = 1.5708f; })));
    EXPECT_NO_THROW(validate_scene(with([](Light& l) {
        l.type = LightType::Point;
        l.direction = glm::vec3(NAN);  // a point light has no direction to check
    })));
    EXPECT_EQ(validation_error(with([](Light& l) { l.position.y = INFINITY; })),
              "quad.json: light 1 has a non-finite position (0, inf, 0)");
    EXPECT_EQ(validation_error(with([](Light& l) { l.direction = glm::vec3(0.0f); })),
              "quad.json: light 1 has no usable direction (0, 0, 0)");
    EXPECT_EQ(validation_error(with([](Light& l) { l.intensity = -2.0f; })),
              "quad.json: light 1: colour x intensity (-2, -2, -2) is not a finite, non-negative light");
    EXPECT_EQ(validation_error(with([](Light& l) { l.color.y = NAN; })),
              "quad.json: light 1: colour x intensity (1, nan, 1) is not a finite, non-negative light");
    EXPECT_EQ(validation_error(with([](Light& l) { l.range = -1.0f; })),
              "quad.json: light 1: range -1 is not a finite distance >= 0");
    EXPECT_EQ(validation_error(with([](Light& l) { l.inner_cone = 0.5f, l.outer_cone = 0.25f; })),
              "quad.json: light 1: spot cone angles 0.5 and 0.25 (radians) are not 0 <= inner <= outer <= pi/2");
    EXPECT_EQ(validation_error(with([](Light& l) { l.outer_cone = 2.0f; })),
              "quad.json: light 1: spot cone angles 0 and 2 (radians) are not 0 <= inner <= outer <= pi/2");
}

TEST(SceneValidate, EmptyScene) {
    Scene scene = quad_scene();
    scene.instances.clear();
    EXPECT_EQ(validation_error(scene), "quad.json: scene has no triangles");
    Scene nothing;
    nothing.source = "empty.gltf";
    EXPECT_EQ(validation_error(nothing), "empty.gltf: scene has no triangles");
}

TEST(SceneValidate, LoadedAssetsPass) {
    Scene scene;
    scene.source = "bunny+sponza";
    scene.meshes.push_back(load_ply(test::scene("stanford/bunny.ply")));
    scene.materials.emplace_back();
    scene.instances.push_back(Instance{});
    load_obj(test::scene("mcguire/dabrovic-sponza/sponza.obj"), scene);
    EXPECT_NO_THROW(validate_scene(scene));
    EXPECT_EQ(scene.triangle_count(), 69451u + 66450u);
}

TEST(SceneValidate, NanVertexFromAPlyFile) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n";
    const std::filesystem::path path = test::write_file("nan_vertex.ply", ply);
    Scene scene;
    scene.source = path.string();
    scene.meshes.push_back(load_ply(path));
    scene.materials.emplace_back();
    scene.instances.push_back(Instance{});
    const std::string expected = path.string() + ": mesh 0 'nan_vertex': vertex 1 has a non-finite position";
    EXPECT_EQ(validation_error(scene).rfind(expected, 0), 0u) << validation_error(scene);
}

}  // namespace
}  // namespace prism
