// Prism scene files: composition of real models with transforms and materials, and the error messages (file and
// key path) for every kind of mistake.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "core/render/device_scene.h"
#include "core/loaders/load_scene_json.h"
#include "core/util/scene_read_rules.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;

std::filesystem::path write_scene(const std::string& name, const json& document) {
    return test::write_file(name, document.dump(2));
}

// These scenes name the shared assets by absolute path, outside their temporary folder: allowed here as
// --allow-any-path allows it (tests/test_hostile_input.cpp tests the rule itself).
Scene load_anywhere(const std::filesystem::path& path) {
    SceneReadScope any_path(path, /*allow_any_path=*/true);
    return load_scene_json(path);
}

std::string error_message(const std::filesystem::path& path) {
    return test::error_message([&] { (void)load_anywhere(path); });
}

const Instance* find_instance(const Scene& scene, const std::string& name) {
    for (const Instance& instance : scene.instances)
        if (instance.name == name) return &instance;
    return nullptr;
}

json composed_scene() {
    std::string scenes = test::scenes_dir().string();
    return {
        {"camera", {{"position", {0, 1, 5}}, {"target", {0, 0.5, 0}}, {"fov", 40}}},
        {"environment", {{"cubemap", scenes + "/env/cubemap-miramar"}, {"intensity", 0.5}}},
        {"ambient", {0.2, 0.2, 0.2}},
        {"lights",
         {{{"type", "point"}, {"position", {1, 4, 2}}, {"intensity", 10}},
          {{"type", "directional"}, {"direction", {0, -2, 0}}, {"color", {1, 0.9, 0.8}}}}},
        {"materials",
         {{"chrome", {{"diffuse", 0.7}, {"reflectivity", 0.8}}},
          {"glass", {{"transmittance", 0.9}, {"reflectivity", 1}, {"ior", {1.5, 1.52, 1.54}}, {"thickness", 0.01}}},
          {"logo",
           {{"textures",
             {{{"file", scenes + "/gltf/BoxTextured/gltf-separate/CesiumLogoFlat.png"},
               {"mode", "decal"},
               {"env_color", {1, 0, 0}},
               {"uv_set", 1}}}}}}}},
        {"objects",
         {{{"file", scenes + "/stanford/bunny_res2.ply"},
           {"name", "bunny"},
           {"transform", {{"translate", {1, 0, 0}}, {"rotate", {{"axis", {0, 1, 0}}, {"degrees", 90}}}, {"scale", 10}}},
           {"material", "chrome"}},
          {{"file", scenes + "/stanford/bunny_res2.ply"},
           {"name", "glass bunny"},
           {"transform", {{"rotate", {{"quaternion", {0, 0, 0, 1}}}}, {"scale", {1, 2, 3}}}},
           {"material", "glass"}},
          {{"file", scenes + "/gltf/Box/Box.glb"},
           {"name", "box"},
           {"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 3, 0, 1}}}}}};
}

TEST(SceneJson, ComposesPlyAndGltfWithTransformsAndMaterials) {
    Scene scene = load_anywhere(write_scene("composed.json", composed_scene()));
    ASSERT_TRUE(scene.has_camera);
    EXPECT_EQ(scene.camera.vertical_fov_degrees, 40.0f);
    EXPECT_EQ(scene.camera.target, glm::vec3(0, 0.5f, 0));
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::CubeMap);
    EXPECT_EQ(scene.environment.textures.size(), 6u);
    EXPECT_EQ(scene.environment.intensity, 0.5f);
    EXPECT_EQ(scene.ambient_light, glm::vec3(0.2f));
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.lights[1].direction, glm::vec3(0, -1, 0));

    const Instance* bunny = find_instance(scene, "bunny");
    const Instance* glass_bunny = find_instance(scene, "glass bunny");
    const Instance* box = find_instance(scene, "box");
    ASSERT_TRUE(bunny && glass_bunny && box);
    EXPECT_EQ(scene.meshes[bunny->mesh].triangles.size(), 16301u);
    // translate * rotate(90 about Y) * scale(10): object +X goes to world -Z, ten times longer, shifted by +1 in x.
    glm::vec3 moved = bunny->transform * glm::vec4(1, 0, 0, 1);
    EXPECT_NEAR(moved.x, 1.0f, 1e-5f);
    EXPECT_NEAR(moved.z, -10.0f, 1e-5f);
    EXPECT_EQ(glm::vec3(glass_bunny->transform * glm::vec4(1, 1, 1, 1)), glm::vec3(1, 2, 3));
    // The box keeps the glTF node transform under the object's matrix.
    EXPECT_NEAR(box->transform[3].y, 3.0f, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec3(box->transform[0])), 2.0f, 1e-5f);

    // Material overrides: the PLYs take the named materials, the box keeps its own; the two bunnies are
    // instances of one mesh, each with its own material.
    EXPECT_EQ(bunny->mesh, glass_bunny->mesh);
    ASSERT_NE(bunny->material_override, kNoMaterialOverride);
    ASSERT_NE(glass_bunny->material_override, kNoMaterialOverride);
    EXPECT_EQ(box->material_override, kNoMaterialOverride);
    const Material& chrome = scene.materials[bunny->material_override];
    EXPECT_EQ(chrome.name, "chrome");
    EXPECT_EQ(chrome.reflectivity, 0.8f);
    EXPECT_EQ(chrome.diffuse, glm::vec3(0.7f));
    const Material& glass = scene.materials[glass_bunny->material_override];
    EXPECT_EQ(glass.name, "glass");
    EXPECT_EQ(glass.ior, glm::vec3(1.5f, 1.52f, 1.54f));
    EXPECT_EQ(glass.thickness, 0.01f);
    EXPECT_NEAR(glass.fresnel_bias, std::pow(0.52f / 2.52f, 2.0f), 1e-6f);  // Schlick default
    EXPECT_NE(scene.materials[scene.meshes[box->mesh].triangle_materials[0]].name, "chrome");

    const Material* logo = nullptr;
    for (const Material& material : scene.materials)
        if (material.name == "logo") logo = &material;
    ASSERT_NE(logo, nullptr);
    ASSERT_EQ(logo->textures.size(), 1u);
    EXPECT_EQ(logo->textures[0].mode, TextureMode::Decal);
    EXPECT_EQ(logo->textures[0].uv_set, 1u);
    EXPECT_EQ(logo->textures[0].environment_color, glm::vec4(1, 0, 0, 1));
    EXPECT_GT(scene.textures[logo->textures[0].texture].width, 0);
    EXPECT_EQ(scene.triangle_count(), 2 * 16301u + 12u);
}

TEST(SceneJson, SameFileAndMaterialIsInstancedNotCopied) {
    json document = composed_scene();
    document["objects"][1]["material"] = "chrome";  // now both bunnies are (file, chrome)
    Scene scene = load_anywhere(write_scene("instanced.json", document));
    EXPECT_EQ(find_instance(scene, "bunny")->mesh, find_instance(scene, "glass bunny")->mesh);
}

TEST(SceneJson, PathsAreRelativeToTheSceneFile) {
    std::filesystem::path folder = test::temp_dir("relative_scene");
    std::filesystem::create_directories(folder / "models");
    std::ofstream(folder / "models" / "tri.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                    "property float y\nproperty float z\nelement face 1\n"
                                                    "property list uchar int vertex_indices\nend_header\n"
                                                    "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    json document = {{"objects", {{{"file", "models/tri.ply"}}}}, {"environment", {{"color", {0.1, 0.2, 0.3}}}}};
    std::ofstream(folder / "scene.json") << document.dump();
    Scene scene = load_scene_json(folder / "scene.json");
    EXPECT_EQ(scene.triangle_count(), 1u);
    EXPECT_FALSE(scene.has_camera);
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::Constant);
    EXPECT_EQ(scene.environment.color, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(scene.materials.at(scene.meshes[0].triangle_materials[0]).name, "default");
}

TEST(SceneJson, ExampleSceneInDocsLoads) {
    std::filesystem::path example = std::filesystem::path(PRISM_SOURCE_DIR) / "docs/examples/bunny-and-helmet.json";
    LoadOptions options;
    options.allow_any_path = true;  // the example reads the shared scenes beside the repository
    Scene scene = load_scene(example.string(), options);
    EXPECT_EQ(scene.instances.size(), 4u);
    EXPECT_EQ(scene.triangle_count(), 2 + 2 * 69451u + 15452u);
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::CubeMap);
    EXPECT_TRUE(scene.has_camera);
}

TEST(SceneJson, SpotLightsExampleLoads) {
    std::filesystem::path example = std::filesystem::path(PRISM_SOURCE_DIR) / "docs/examples/spot-lights.json";
    LoadOptions options;
    options.allow_any_path = true;
    Scene scene = load_scene(example.string(), options);
    ASSERT_EQ(scene.lights.size(), 4u);
    const Light& red = scene.lights[0];
    EXPECT_EQ(red.type, LightType::Spot);
    EXPECT_EQ(red.position, glm::vec3(-2.5f, 3.0f, 1.5f));
    EXPECT_NEAR(glm::length(red.direction), 1.0f, 1e-6f);
    EXPECT_NEAR(red.direction.x, 1.5f / std::sqrt(1.5f * 1.5f + 2.7f * 2.7f + 1.5f * 1.5f), 1e-6f);
    EXPECT_FLOAT_EQ(red.inner_cone, glm::radians(14.0f));
    EXPECT_FLOAT_EQ(red.outer_cone, glm::radians(22.0f));
    EXPECT_EQ(red.range, 0.0f);
    EXPECT_EQ(scene.lights[3].type, LightType::Point);
    EXPECT_EQ(scene.lights[3].range, 1.0f);
}

// Each case: a change to the valid document and the exact message it must produce after "<file>: ".
struct BrokenCase {
    const char* name;
    void (*breaks)(json&);
    const char* message;
};

const BrokenCase kBrokenCases[] = {
    {"unknown_top", [](json& d) { d["objcts"] = json::array(); }, "objcts: unknown key"},
    {"unknown_nested",
     [](json& d) {
         d["objects"][0]["transform"]["translation"] = {0, 0, 0};
     },
     "objects[0].transform.translation: unknown key"},
    {"unknown_material_field", [](json& d) { d["materials"]["chrome"]["roughness"] = 0.5; },
     "materials.chrome.roughness: unknown key"},
    {"scale_type",
     [](json& d) {
         d["objects"][2].erase("matrix");
         d["objects"][2]["transform"] = {{"scale", "big"}};
     },
     "objects[2].transform.scale: expected a number or 3 numbers"},
    {"scale_length",
     [](json& d) {
         d["objects"][0]["transform"]["scale"] = {1, 2};
     },
     "objects[0].transform.scale: expected a number or 3 numbers"},
    {"translate_type", [](json& d) { d["objects"][1]["transform"]["translate"] = 3; },
     "objects[1].transform.translate: expected 3 numbers"},
    {"matrix_length",
     [](json& d) {
         d["objects"][2]["matrix"] = {1, 0, 0};
     },
     "objects[2].matrix: expected 16 numbers"},
    {"both_transforms", [](json& d) { d["objects"][2]["transform"] = json::object(); },
     "objects[2]: give either transform or matrix"},
    {"camera_fov", [](json& d) { d["camera"]["fov"] = "wide"; }, "camera.fov: expected a number"},
    {"light_type", [](json& d) { d["lights"][0]["type"] = "area"; },
     "lights[0].type: expected \"point\", \"spot\" or \"directional\""},
    {"spot_direction", [](json& d) { d["lights"][0]["type"] = "spot"; },
     "lights[0].direction: a spot light needs a direction"},
    {"point_cone", [](json& d) { d["lights"][0]["outer_cone_degrees"] = 30; },
     "lights[0].outer_cone_degrees: a point light has no outer_cone_degrees"},
    {"directional_range", [](json& d) { d["lights"][1]["range"] = 5; },
     "lights[1].range: a directional light has no range"},
    {"range_zero", [](json& d) { d["lights"][0]["range"] = 0; }, "lights[0].range: must be a distance > 0"},
    {"spot_cone_order",
     [](json& d) {
         d["lights"][0] = {{"type", "spot"},
                           {"position", {0, 2, 0}},
                           {"direction", {0, -1, 0}},
                           {"inner_cone_degrees", 30},
                           {"outer_cone_degrees", 20}};
     },
     "lights[0]: a spot's cone needs 0 <= inner_cone_degrees <= outer_cone_degrees <= 90"},
    {"reflectivity_range", [](json& d) { d["materials"]["chrome"]["reflectivity"] = 2; },
     "materials.chrome.reflectivity: expected a number in [0, 1]"},
    {"texture_mode", [](json& d) { d["materials"]["logo"]["textures"][0]["mode"] = "multiply"; },
     "materials.logo.textures[0].mode: expected replace, decal, modulate or blend"},
    {"unknown_material", [](json& d) { d["objects"][0]["material"] = "gold"; },
     "objects[0].material: no material named 'gold' in materials"},
    {"objects_type", [](json& d) { d["objects"] = json::object(); }, "objects: expected an array"},
};

TEST(SceneJson, MistakesNameTheFileAndKeyPath) {
    for (const BrokenCase& broken : kBrokenCases) {
        SCOPED_TRACE(broken.name);
        json document = composed_scene();
        broken.breaks(document);
        std::filesystem::path path = write_scene(std::string("broken_") + broken.name + ".json", document);
        EXPECT_EQ(error_message(path), path.string() + ": " + broken.message);
    }
}

TEST(SceneJson, MissingObjectFileNamesKeyAndFile) {
    json document = composed_scene();
    document["objects"][1]["file"] = "no_such_model.ply";
    std::filesystem::path path = write_scene("missing_object.json", document);
    std::string message = error_message(path);
    EXPECT_EQ(message.rfind(path.string() + ": objects[1].file: no such file", 0), 0u) << message;
    EXPECT_NE(message.find("no_such_model.ply"), std::string::npos) << message;
}

TEST(SceneJson, MissingTextureAndCubeMapNameTheKey) {
    json document = composed_scene();
    document["materials"]["logo"]["textures"][0]["file"] = "nothing.png";
    std::filesystem::path path = write_scene("missing_texture.json", document);
    EXPECT_EQ(error_message(path).rfind(path.string() + ": materials.logo.textures[0].file: no such file", 0), 0u);
    document = composed_scene();
    document["environment"]["cubemap"] = "no_sky";
    path = write_scene("missing_sky.json", document);
    EXPECT_EQ(error_message(path).rfind(path.string() + ": environment.cubemap: no such folder", 0), 0u);
}

TEST(SceneJson, InvalidJsonReportsWhere) {
    std::filesystem::path path = test::write_file("syntax.json", "{\n  \"objects\": [\n    {\"file\": }\n  ]\n}\n");
    std::string message = error_message(path);
    EXPECT_EQ(message.rfind(path.string() + ": invalid JSON: ", 0), 0u) << message;
    EXPECT_NE(message.find("line 3"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(SceneJson, ErrorsInsideAModelFileNameThatFile) {
    std::filesystem::path broken_model =
        test::write_file("broken_model.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
    json document = {{"objects", {{{"file", broken_model.string()}}}}};
    std::filesystem::path path = write_scene("broken_model_scene.json", document);
    EXPECT_EQ(error_message(path).rfind(broken_model.string() + ":", 0), 0u) << error_message(path);
}

}  // namespace
}  // namespace prism

namespace prism {

// Two instances of one mesh with different material overrides: one set of vertices and one BVH on the device,
// each instance reading its own material.
TEST(SceneJson, MaterialOverridesShareTheMeshOnTheDevice) {
    Scene scene;
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.triangle_materials = {0};
    scene.meshes.push_back(mesh);
    scene.materials.resize(3);
    scene.instances.push_back(Instance{0, glm::mat4(1.0f), "own"});
    scene.instances.push_back(Instance{0, glm::mat4(1.0f), "red", 1});
    scene.instances.push_back(Instance{0, glm::mat4(1.0f), "blue", 2});
    scene.instances.push_back(Instance{0, glm::mat4(1.0f), "red again", 1});
    DeviceScene device = build_device_scene(scene);
    EXPECT_EQ(device.vertices.size(), 3u);
    EXPECT_EQ(device.triangles.size(), 1u);
    std::vector<uint32_t> materials;
    for (const ::Instance& instance : device.instances) {
        EXPECT_EQ(instance.root, device.instances[0].root);  // one BVH root
        materials.push_back(device.triangle_shading.at(instance.first_shading).material);
    }
    EXPECT_EQ(materials, (std::vector<uint32_t>{0, 1, 2, 1}));
    EXPECT_EQ(device.instances[1].first_shading, device.instances[3].first_shading);  // one copy per (mesh, material)
}

}  // namespace prism
