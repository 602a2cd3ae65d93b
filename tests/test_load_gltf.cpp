// glTF loading: every Khronos sample in ../shared/scenes/gltf, plus small generated files for the corner cases
// (sparse accessors, strips and fans, mirrored nodes, extensions) and malformed input.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <random>
#include <set>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <webp/encode.h>

#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/loaders/gltf_material.h"
#include "core/loaders/load_gltf.h"
#include "core/loaders/scene_loader.h"
#include "tests/gltf_builder.h"
#include "tests/gltf_compressed.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_gltf(path, scene);
    return scene;
}

std::string read_bytes(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// The JSON chunk of a .glb, read independently of tinygltf to check the loader against the file's own values.
json glb_json(const std::filesystem::path& path) {
    std::string bytes = read_bytes(path);
    uint32_t length;
    std::memcpy(&length, bytes.data() + 12, 4);
    return json::parse(bytes.substr(20, length));
}

const Instance* find_instance(const Scene& scene, const std::string& name) {
    for (const Instance& instance : scene.instances)
        if (instance.name == name) return &instance;
    return nullptr;
}

glm::vec3 world_geometric_normal(const Scene& scene, const Instance& instance, size_t triangle) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    glm::uvec3 t = mesh.triangles[triangle];
    auto world = [&](uint32_t i) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[i], 1.0f)); };
    return glm::normalize(glm::cross(world(t.y) - world(t.x), world(t.z) - world(t.x)));
}

std::string error_message(const std::filesystem::path& path) {
    return test::error_message([&] { (void)load(path); });
}

// Loading fails in one line that starts with the file's path and says `what`.
void expect_error_naming_the_file(const std::filesystem::path& path, const std::string& what) {
    std::string message = error_message(path);
    EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
}

// One triangle's positions: the smallest mesh a malformed file needs around the part it breaks.
int triangle_positions(GltfBuilder& gltf) { return gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0}); }

// ---- The real sample models ----------------------------------------------------------------------------------

TEST(LoadGltf, EverySampleModelLoads) {
    int files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(test::scene("gltf"))) {
        std::string extension = entry.path().extension().string();
        if (extension != ".glb" && extension != ".gltf") continue;
        SCOPED_TRACE(entry.path().string());
        Scene scene = load(entry.path());
        EXPECT_GT(scene.triangle_count(), 0u);
        EXPECT_FALSE(scene.materials.empty());
        for (const Mesh& mesh : scene.meshes) {
            ASSERT_EQ(mesh.triangle_materials.size(), mesh.triangles.size());
            for (const glm::uvec3& t : mesh.triangles)
                ASSERT_LT(glm::max(t.x, glm::max(t.y, t.z)), mesh.positions.size());
        }
        ++files;
    }
    EXPECT_GE(files, 24);  // 22 folders, some with a gltf-separate/ variant too
}

TEST(LoadGltf, BoxHasTwelveTriangles) { EXPECT_EQ(load(test::scene("gltf/Box/Box.glb")).triangle_count(), 12u); }

TEST(LoadGltf, DamagedHelmetCountsAndTextureMatchInBothForms) {
    Scene binary = load(test::scene("gltf/DamagedHelmet/DamagedHelmet.glb"));
    Scene separate = load(test::scene("gltf/DamagedHelmet/gltf-separate/DamagedHelmet.gltf"));
    EXPECT_EQ(binary.triangle_count(), 15452u);  // its one index accessor holds 46,356 indices
    EXPECT_EQ(separate.triangle_count(), 15452u);
    ASSERT_EQ(binary.materials.size(), 1u);
    ASSERT_EQ(binary.materials[0].textures.size(), 1u);  // the base colour stack; the other maps have their slots
    EXPECT_TRUE(binary.materials[0].emissive_map && binary.materials[0].metal_rough_map &&
                binary.materials[0].normal_map && binary.materials[0].occlusion_map);
    const Texture& albedo = binary.textures[binary.materials[0].textures[0].texture];
    EXPECT_EQ(albedo.width, 2048);
    EXPECT_EQ(albedo.encoding, TextureEncoding::Srgb8);
    EXPECT_GT(binary.materials[0].emissive.x, 0.0f);
    ASSERT_EQ(separate.textures.size(), binary.textures.size());
    EXPECT_EQ(separate.textures[separate.materials[0].textures[0].texture].texels, albedo.texels);
}

TEST(LoadGltf, MetalRoughSpheresOneInstancePerPrimitive) {
    std::filesystem::path path = test::scene("gltf/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.glb");
    Scene scene = load(path);
    json file = glb_json(path);
    size_t placed_primitives = 0;  // 119 nodes, 102 of them with a mesh, 123 primitives among those meshes
    for (const json& node : file["nodes"])
        if (node.contains("mesh")) placed_primitives += file["meshes"][node["mesh"].get<int>()]["primitives"].size();
    EXPECT_EQ(scene.instances.size(), placed_primitives);
    EXPECT_EQ(scene.instances.size(), 123u);
    EXPECT_EQ(scene.meshes.size(), 123u);
    EXPECT_EQ(scene.triangle_count(), 1040409u);
    // Roughness-0 metal spheres are mirrors, dielectric ones are not.
    bool mirror = false, matte = false;
    for (const Material& material : scene.materials) {
        mirror |= material.reflectivity > 0.9f;
        matte |= material.reflectivity == 0.0f;
    }
    EXPECT_TRUE(mirror);
    EXPECT_TRUE(matte);
}

TEST(LoadGltf, OrientationTestWorldTransformsMatchTheFile) {
    std::filesystem::path path = test::scene("gltf/OrientationTest/OrientationTest.glb");
    Scene scene = load(path);
    json file = glb_json(path);
    int checked = 0;
    for (const json& node : file["nodes"]) {
        const Instance* instance = find_instance(scene, node["name"]);
        ASSERT_NE(instance, nullptr) << node["name"];
        glm::mat4 expected(1.0f);
        if (node.contains("matrix")) {
            for (int i = 0; i < 16; ++i) expected[i / 4][i % 4] = node["matrix"][i].get<float>();
        } else {
            glm::vec3 t(0.0f), s(1.0f);
            glm::quat r(1.0f, 0.0f, 0.0f, 0.0f);
            if (node.contains("translation"))
                t = {node["translation"][0], node["translation"][1], node["translation"][2]};
            if (node.contains("scale")) s = {node["scale"][0], node["scale"][1], node["scale"][2]};
            if (node.contains("rotation"))
                r = glm::quat(node["rotation"][3].get<float>(), node["rotation"][0].get<float>(),
                              node["rotation"][1].get<float>(), node["rotation"][2].get<float>());
            // T * R * S written out column by column, independent of the loader's GLM calls.
            glm::mat3 rs = glm::mat3_cast(r);
            for (int c = 0; c < 3; ++c) expected[c] = glm::vec4(rs[c] * s[c], 0.0f);
            expected[3] = glm::vec4(t, 1.0f);
        }
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) EXPECT_NEAR(instance->transform[c][r], expected[c][r], 1e-5f) << node["name"];
        ++checked;
    }
    EXPECT_EQ(checked, 13);
    // Spot values straight from the file: ArrowX1 sits at x = 5, rotated about X by -35 degrees.
    const Instance* arrow = find_instance(scene, "ArrowX1");
    ASSERT_NE(arrow, nullptr);
    EXPECT_NEAR(arrow->transform[3].x, 5.0f, 1e-6f);
    EXPECT_NEAR(arrow->transform[1].y, std::cos(glm::radians(35.0f)), 1e-4f);
    EXPECT_NEAR(arrow->transform[1].z, -std::sin(glm::radians(35.0f)), 1e-4f);
}

TEST(LoadGltf, CamerasFileGivesThePerspectiveCamera) {
    Scene scene = load(test::scene("gltf/Cameras/Cameras.gltf"));
    ASSERT_TRUE(scene.has_camera);
    EXPECT_NEAR(scene.camera.vertical_fov_degrees, glm::degrees(0.7f), 1e-4f);
    EXPECT_NEAR(scene.camera.position.z, 3.0f, 1e-6f);
    EXPECT_NEAR(scene.camera.position.x, 0.5f, 1e-6f);
    EXPECT_NEAR(scene.camera.target.z, 2.0f, 1e-5f);  // looks down -Z
    EXPECT_EQ(scene.triangle_count(), 2u);
}

TEST(LoadGltf, TextureTransformRowsFollowTheExtension) {
    Scene scene = load(test::scene("gltf/TextureTransformTest/TextureTransformTest.gltf"));
    auto material = [&](const std::string& name) -> const Material& {
        for (const Material& m : scene.materials)
            if (m.name == name) return m;
        throw std::runtime_error("no material " + name);
    };
    const TextureLayer& offset = material("Offset UV").textures.at(0);
    EXPECT_EQ(offset.uv_row0, glm::vec3(1.0f, 0.0f, 0.5f));
    EXPECT_EQ(offset.uv_row1, glm::vec3(0.0f, 1.0f, 0.5f));
    const TextureLayer& rotation = material("Rotation").textures.at(0);
    float angle = 0.39269908169872414f;
    EXPECT_NEAR(rotation.uv_row0.x, std::cos(angle), 1e-6f);
    EXPECT_NEAR(rotation.uv_row0.y, std::sin(angle), 1e-6f);  // the sample viewer's direction
    EXPECT_NEAR(rotation.uv_row1.x, -std::sin(angle), 1e-6f);
    const TextureLayer& scale = material("Scale").textures.at(0);
    EXPECT_EQ(scale.uv_row0, glm::vec3(1.5f, 0.0f, 0.0f));
    EXPECT_EQ(material("Correct").textures.at(0).uv_row0, glm::vec3(1.0f, 0.0f, 0.0f));
}

TEST(LoadGltf, TransmissiveSamplesGetTransmittance) {
    for (const char* file : {"gltf/TransmissionTest/TransmissionTest.glb", "gltf/GlassVaseFlowers/GlassVaseFlowers.glb",
                             "gltf/AttenuationTest/AttenuationTest.glb"}) {
        SCOPED_TRACE(file);
        Scene scene = load(test::scene(file));
        bool transmissive = false;
        for (const Material& material : scene.materials) {
            if (material.transmittance <= 0.0f) continue;
            transmissive = true;
            EXPECT_LT(material.fresnel_bias, 0.2f);  // Schlick F0 of a dielectric, not the opaque R_f = 1
            EXPECT_NEAR(material.fresnel_bias + material.fresnel_scale, 1.0f, 1e-6f);
        }
        EXPECT_TRUE(transmissive);
    }
}

// AttenuationTest's rows vary attenuationDistance: each becomes its own Beer-Lambert coefficient (not one flat
// tint for all), and a shorter distance absorbs more.
TEST(LoadGltf, AttenuationDistanceBecomesAbsorption) {
    Scene scene = load(test::scene("gltf/AttenuationTest/AttenuationTest.glb"));
    std::set<float> coefficients;
    for (const Material& material : scene.materials)
        if (material.transmittance > 0.0f && glm::length(material.absorption) > 0.0f)
            coefficients.insert(glm::length(material.absorption));
    EXPECT_GE(coefficients.size(), 5u);
}

// IridescenceSuzanne: three films (KHR_materials_iridescence, required by the file) over a dielectric, a metal and
// a glass, the last with a thickness texture; read without the "not supported" warning.
TEST(LoadGltf, IridescentFilmsAreRead) {
    Scene scene = load(test::scene("gltf/IridescenceSuzanne/IridescenceSuzanne.glb"));
    for (const std::string& warning : scene.warnings) EXPECT_EQ(warning.find("iridescence"), std::string::npos);
    std::vector<const Material*> films;
    for (const Material& material : scene.materials)
        if (material.iridescence > 0.0f) films.push_back(&material);
    ASSERT_EQ(films.size(), 3u);
    int metals = 0, glasses = 0, textured = 0;
    for (const Material* film : films) {
        EXPECT_EQ(film->iridescence, 1.0f);
        metals += film->metallic == 1.0f;
        glasses += film->transmittance == 1.0f;
        if (film->iridescence_thickness_map) {
            ++textured;
            EXPECT_FLOAT_EQ(film->iridescence_ior, 1.8f);
            EXPECT_EQ(film->iridescence_thickness_min, 200.0f);
            EXPECT_EQ(film->iridescence_thickness_max, 600.0f);
            EXPECT_GT(film->transmittance, 0.0f);
        } else {
            EXPECT_FLOAT_EQ(film->iridescence_ior, 1.33f);
            EXPECT_EQ(film->iridescence_thickness_min, 100.0f) << "the default";
            EXPECT_EQ(film->iridescence_thickness_max, 400.0f);
        }
    }
    EXPECT_EQ(metals, 1);
    EXPECT_EQ(glasses, 1);
    EXPECT_EQ(textured, 1);
}

TEST(LoadGltf, VertexColoursArePresent) {
    for (const char* file : {"gltf/VertexColorTest/VertexColorTest.glb", "gltf/BoxVertexColors/BoxVertexColors.glb"}) {
        SCOPED_TRACE(file);
        Scene scene = load(test::scene(file));
        bool colored = false;
        for (const Mesh& mesh : scene.meshes)
            if (!mesh.colors.empty()) {
                colored = true;
                EXPECT_EQ(mesh.colors.size(), mesh.positions.size());
                EXPECT_TRUE(scene.materials[mesh.triangle_materials[0]].use_vertex_colors);
            }
        EXPECT_TRUE(colored);
    }
}

// ---- Generated files -------------------------------------------------------------------------------------------

TEST(LoadGltf, SparseAccessorSubstitutesValues) {
    GltfBuilder gltf;
    int base = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int sparse_indices = gltf.view(std::vector<uint8_t>{1, 0, 0, 0});  // one UNSIGNED_BYTE index, padded
    int sparse_values = gltf.view(std::vector<float>{5, 6, 7});
    json accessor = gltf.document["accessors"][base];
    accessor["sparse"] = {{"count", 1},
                          {"indices", {{"bufferView", sparse_indices}, {"componentType", 5121}}},
                          {"values", {{"bufferView", sparse_values}}}};
    int positions = gltf.accessor(accessor);
    // A sparse accessor without a bufferView starts from zeros.
    int zero_based = gltf.accessor({{"componentType", 5126},
                                    {"count", 3},
                                    {"type", "VEC3"},
                                    {"sparse",
                                     {{"count", 1},
                                      {"indices", {{"bufferView", sparse_indices}, {"componentType", 5121}}},
                                      {"values", {{"bufferView", sparse_values}}}}}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}, {"name", "sparse"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", zero_based}}}}})}, {"name", "zeros"}});
    Scene scene = load(gltf.write("sparse.gltf"));
    ASSERT_EQ(scene.meshes.size(), 2u);
    const Mesh& sparse = scene.meshes[scene.instances[0].mesh];
    EXPECT_EQ(sparse.positions[0], glm::vec3(0, 0, 0));
    EXPECT_EQ(sparse.positions[1], glm::vec3(5, 6, 7));
    EXPECT_EQ(sparse.positions[2], glm::vec3(0, 1, 0));
    const Mesh& zeros = scene.meshes[scene.instances[1].mesh];
    EXPECT_EQ(zeros.positions[0], glm::vec3(0));
    EXPECT_EQ(zeros.positions[1], glm::vec3(5, 6, 7));
}

TEST(LoadGltf, StridedNormalizedAttributes) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    // COLOR_0 as normalized UNSIGNED_BYTE VEC4 interleaved with 4 padding bytes per element (byteStride 8).
    int colors_view = gltf.view(
        std::vector<uint8_t>{255, 0, 0, 255, 9, 9, 9, 9, 0, 255, 0, 255, 9, 9, 9, 9, 0, 0, 255, 128, 9, 9, 9, 9}, 8);
    int colors = gltf.accessor(
        {{"bufferView", colors_view}, {"componentType", 5121}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}});
    // TEXCOORD_0 as normalized UNSIGNED_SHORT.
    int uv_view = gltf.view(std::vector<uint16_t>{0, 65535, 65535, 0, 32768, 32768});
    int uv = gltf.accessor(
        {{"bufferView", uv_view}, {"componentType", 5123}, {"normalized", true}, {"count", 3}, {"type", "VEC2"}});
    gltf.node(
        {{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}, {"COLOR_0", colors}, {"TEXCOORD_0", uv}}}}})}});
    Scene scene = load(gltf.write("strided.gltf"));
    const Mesh& mesh = scene.meshes.at(0);
    ASSERT_EQ(mesh.colors.size(), 3u);
    EXPECT_EQ(mesh.colors[0], glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(mesh.colors[1], glm::vec4(0, 1, 0, 1));
    EXPECT_NEAR(mesh.colors[2].w, 128.0f / 255.0f, 1e-6f);
    EXPECT_EQ(mesh.uv0[0], glm::vec2(0, 1));
    EXPECT_NEAR(mesh.uv0[2].x, 32768.0f / 65535.0f, 1e-6f);
}

TEST(LoadGltf, TriangleStripAndFanKeepFrontFaces) {
    GltfBuilder gltf;
    // A zig-zag strip in the XY plane and a fan around the origin, both counter-clockwise seen from +Z.
    int strip_positions = gltf.positions({0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0});
    int strip_indices = gltf.indices({1, 0, 3, 2, 4});
    int fan_positions = gltf.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0});
    gltf.node(
        {{"mesh",
          gltf.mesh({{{"attributes", {{"POSITION", strip_positions}}}, {"indices", strip_indices}, {"mode", 5}}})},
         {"name", "strip"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", fan_positions}}}, {"mode", 6}}})}, {"name", "fan"}});
    Scene scene = load(gltf.write("strip_fan.gltf"));
    for (const char* name : {"strip", "fan"}) {
        SCOPED_TRACE(name);
        const Instance* instance = find_instance(scene, name);
        ASSERT_NE(instance, nullptr);
        ASSERT_EQ(scene.meshes[instance->mesh].triangles.size(), 3u);
        for (size_t t = 0; t < 3; ++t) EXPECT_GT(world_geometric_normal(scene, *instance, t).z, 0.99f);
    }
    EXPECT_EQ(scene.meshes[find_instance(scene, "fan")->mesh].triangles[0], glm::uvec3(1, 2, 0));
}

TEST(LoadGltf, MirroredNodeGetsReversedWinding) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});  // faces +Z
    int mesh = gltf.mesh({{{"attributes", {{"POSITION", positions}}}}});
    gltf.node({{"mesh", mesh}, {"name", "plain"}, {"scale", {2, 1, 1}}});
    gltf.node({{"mesh", mesh}, {"name", "plain again"}, {"translation", {0, 0, 5}}});
    gltf.node({{"mesh", mesh}, {"name", "mirrored"}, {"scale", {-2, 1, 1}}});
    // The mirror may come from a parent: the world transform decides.
    int child = gltf.node({{"mesh", mesh}, {"name", "mirrored child"}});
    gltf.node({{"children", {child}}, {"scale", {1, -1, 1}}});
    Scene scene = load(gltf.write("mirrored.gltf"));
    const Instance* plain = find_instance(scene, "plain");
    const Instance* mirrored = find_instance(scene, "mirrored");
    const Instance* mirrored_child = find_instance(scene, "mirrored child");
    ASSERT_TRUE(plain && mirrored && mirrored_child);
    EXPECT_EQ(plain->mesh, find_instance(scene, "plain again")->mesh);  // one Mesh for every use of a glTF mesh
    EXPECT_NE(plain->mesh, mirrored->mesh);                             // except a mirrored copy...
    EXPECT_EQ(mirrored->mesh, mirrored_child->mesh);                    // ...made once and shared
    EXPECT_EQ(scene.meshes.size(), 2u);
    EXPECT_GT(world_geometric_normal(scene, *plain, 0).z, 0.99f);
    EXPECT_GT(world_geometric_normal(scene, *mirrored, 0).z, 0.99f);
    EXPECT_GT(world_geometric_normal(scene, *mirrored_child, 0).z, 0.99f);
}

TEST(LoadGltf, PointsAndLinesGiveOneWarning) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"mode", 0}},
                                   {{"attributes", {{"POSITION", positions}}}, {"mode", 1}},
                                   {{"attributes", {{"POSITION", positions}}}, {"mode", 4}}})}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"mode", 3}}})}});
    Scene scene = load(gltf.write("points.gltf"));
    EXPECT_EQ(scene.triangle_count(), 1u);
    int point_warnings = 0;
    for (const std::string& warning : scene.warnings)
        point_warnings += warning.find("points and lines") != std::string::npos;
    EXPECT_EQ(point_warnings, 1);
}

// KHR_materials_clearcoat's factors and textures become the material's coat; a file that requires the extension
// loads without the "not supported" warning.
TEST(LoadGltf, ClearcoatIsRead) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.document["extensionsUsed"] = {"KHR_materials_clearcoat"};
    gltf.document["extensionsRequired"] = {"KHR_materials_clearcoat"};
    gltf.document["materials"] =
        json::array({{{"name", "car paint"},
                      {"pbrMetallicRoughness", {{"baseColorFactor", {0.6, 0.0, 0.0, 1}}, {"metallicFactor", 0.5}}},
                      {"extensions",
                       {{"KHR_materials_clearcoat", {{"clearcoatFactor", 0.8}, {"clearcoatRoughnessFactor", 0.25}}}}}},
                     {{"name", "over range"},
                      {"extensions",
                       {{"KHR_materials_clearcoat", {{"clearcoatFactor", 3.0}, {"clearcoatRoughnessFactor", -1}}}}}}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"material", 0}},
                                   {{"attributes", {{"POSITION", positions}}}, {"material", 1}}})}});
    Scene scene = load(gltf.write("clearcoat.gltf"));
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_FLOAT_EQ(scene.materials[0].clearcoat, 0.8f);
    EXPECT_FLOAT_EQ(scene.materials[0].clearcoat_roughness, 0.25f);
    EXPECT_FALSE(scene.materials[0].clearcoat_map);
    EXPECT_EQ(scene.materials[1].clearcoat, 1.0f) << "clamped to [0, 1]";
    EXPECT_EQ(scene.materials[1].clearcoat_roughness, 0.0f);
}

TEST(LoadGltf, MaterialExtensionsMapOntoTheSeedModel) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.document["materials"] = json::array(
        {{{"name", "metal"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.9, 0.6, 0.2, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}},
         {{"name", "glass"},
          {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
          {"extensions",
           {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
            {"KHR_materials_ior", {{"ior", 1.7}}},
            {"KHR_materials_volume", {{"thicknessFactor", 0.5}, {"attenuationColor", {0.5, 0.8, 1.0}}}},
            {"KHR_materials_dispersion", {{"dispersion", 1.0}}},
            {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {1.0, 0.5, 0.5}}}}}}},
         {{"name", "thin"},
          {"pbrMetallicRoughness", {{"metallicFactor", 0}}},
          {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}}}}}},
         {{"name", "blend"},
          {"alphaMode", "BLEND"},
          {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 0.25}}, {"metallicFactor", 0}}}},
         {{"name", "lamp"},
          {"emissiveFactor", {1, 0.5, 0}},
          {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}}});
    json primitives = json::array();
    for (int m = 0; m < 5; ++m) primitives.push_back({{"attributes", {{"POSITION", positions}}}, {"material", m}});
    primitives.push_back({{"attributes", {{"POSITION", positions}}}});  // no material: Prism's default
    gltf.node({{"mesh", gltf.mesh(primitives)}});
    Scene scene = load(gltf.write("materials.gltf"));
    ASSERT_EQ(scene.materials.size(), 6u);
    auto by_name = [&](const std::string& name) -> const Material& {
        for (const Material& m : scene.materials)
            if (m.name == name) return m;
        throw std::runtime_error("no material " + name);
    };
    const Material& metal = by_name("metal");
    EXPECT_FLOAT_EQ(metal.reflectivity, 1.0f);
    // Metals tint reflections with their base colour: the kernel mixes per hit, from the metallic factor.
    EXPECT_TRUE(metal.metal_rough);
    EXPECT_EQ(metal.metallic, 1.0f);
    EXPECT_EQ(metal.roughness, 0.0f);
    EXPECT_EQ(metal.specular, glm::vec3(1.0f));
    EXPECT_EQ(metal.transmittance, 0.0f);
    // Opaque glTF surfaces carry the dielectric's Schlick term; the kernel weighs it by 1 - metallic.
    EXPECT_NEAR(metal.fresnel_bias, 0.04f, 1e-6f);
    EXPECT_NEAR(metal.fresnel_scale, 0.96f, 1e-6f);

    const Material& glass = by_name("glass");
    EXPECT_EQ(glass.transmittance, 1.0f);
    float f0 = std::pow((1.7f - 1.0f) / (1.7f + 1.0f), 2.0f);  // KHR_materials_specular scales the whole term
    EXPECT_NEAR(glass.fresnel_bias, f0 * 0.5f, 1e-6f);
    EXPECT_NEAR(glass.fresnel_scale, (1.0f - f0) * 0.5f, 1e-6f);
    EXPECT_EQ(glass.fresnel_power, 5.0f);
    EXPECT_NEAR(glass.specular.y, 0.5f, 1e-6f);
    // No attenuationDistance: infinite, so the solid volume absorbs nothing (glTF's default).
    EXPECT_EQ(glass.ambient, glm::vec3(1.0f));
    EXPECT_EQ(glass.absorption, glm::vec3(0.0f));
    EXPECT_EQ(glass.thickness, 0.0f);  // a volume: solid glass
    EXPECT_LT(glass.ior.x, glass.ior.y);
    EXPECT_LT(glass.ior.y, glass.ior.z);
    EXPECT_NEAR(glass.ior.y, 1.7f, 0.01f);
    // Abbe number 20 between the F and C lines: n_F - n_C = (n_d - 1) / V.
    glm::vec3 fc = gltf::dispersive_ior(1.7f, 1.0f);
    EXPECT_GT(fc.z - fc.x, 0.0f);

    const Material& thin = by_name("thin");
    EXPECT_EQ(thin.transmittance, 0.5f);
    EXPECT_EQ(thin.ior, glm::vec3(1.5f));
    EXPECT_EQ(thin.thickness, gltf::kThinWalledThickness);

    const Material& blend = by_name("blend");
    EXPECT_EQ(blend.alpha_mode, AlphaMode::Blend);  // the kernel lets 1 - alpha pass straight through
    EXPECT_FLOAT_EQ(blend.alpha, 0.25f);
    EXPECT_EQ(blend.transmittance, 0.0f);

    EXPECT_EQ(by_name("lamp").emissive, glm::vec3(4.0f, 2.0f, 0.0f));
    EXPECT_EQ(by_name("default").diffuse, glm::vec3(0.8f));
    EXPECT_EQ(by_name("default").reflectivity, 0.0f);
}

TEST(LoadGltf, DispersionFollowsTheAbbeNumber) {
    // dispersion = 20 / V; with Cauchy's model n(F) - n(C) = (n_d - 1) / V exactly.
    float ior = 1.5f, dispersion = 0.5f;
    glm::vec3 rgb = gltf::dispersive_ior(ior, dispersion);
    double abbe = 20.0 / dispersion;
    double b = (ior - 1.0) / (abbe * (1.0 / (0.4861 * 0.4861) - 1.0 / (0.6563 * 0.6563)));
    double a = ior - b / (0.5876 * 0.5876);
    EXPECT_NEAR(rgb.x, a + b / (0.65 * 0.65), 1e-6);
    EXPECT_NEAR(rgb.z, a + b / (0.45 * 0.45), 1e-6);
    EXPECT_EQ(gltf::dispersive_ior(1.5f, 0.0f), glm::vec3(1.5f));
}

TEST(LoadGltf, PunctualLightsAndSecondCameraIgnored) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.document["extensionsUsed"] = {"KHR_lights_punctual"};
    gltf.document["extensions"] = {
        {"KHR_lights_punctual",
         {{"lights",
           {{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 20}, {"range", 7.5}},
            {{"type", "directional"}, {"intensity", 3}},
            {{"type", "spot"}, {"spot", json::object()}},
            {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}}}}}}};
    gltf.document["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
                                {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}};
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    gltf.node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    // Rotated 90 degrees about X: the light's -Z becomes -Y (straight down).
    float h = std::sqrt(0.5f);
    gltf.node({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    gltf.node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    // A spot at (0, 1, 0) turned 90 degrees about Y: its -Z becomes -X.
    gltf.node({{"translation", {0, 1, 0}},
               {"rotation", {0, h, 0, h}},
               {"extensions", {{"KHR_lights_punctual", {{"light", 3}}}}}});
    gltf.node({{"camera", 0}, {"translation", {0, 0, 10}}});
    gltf.node({{"camera", 1}});
    Scene scene = load(gltf.write("lights.gltf"));
    ASSERT_EQ(scene.lights.size(), 4u);
    EXPECT_EQ(scene.lights[0].type, LightType::Point);
    EXPECT_EQ(scene.lights[0].position, glm::vec3(1, 2, 3));
    EXPECT_EQ(scene.lights[0].color, glm::vec3(1, 0.5, 0.25));
    EXPECT_EQ(scene.lights[0].intensity, 20.0f);
    EXPECT_EQ(scene.lights[0].range, 7.5f);
    EXPECT_EQ(scene.lights[1].type, LightType::Directional);
    EXPECT_NEAR(scene.lights[1].direction.y, -1.0f, 1e-5f);
    EXPECT_EQ(scene.lights[1].range, 0.0f);
    // A spot without angles gets the extension's defaults, 0 and pi/4, and no range.
    EXPECT_EQ(scene.lights[2].type, LightType::Spot);
    EXPECT_EQ(scene.lights[2].inner_cone, 0.0f);
    EXPECT_FLOAT_EQ(scene.lights[2].outer_cone, 0.78539816f);
    EXPECT_NEAR(scene.lights[2].direction.z, -1.0f, 1e-6f);
    EXPECT_EQ(scene.lights[2].range, 0.0f);
    EXPECT_EQ(scene.lights[3].type, LightType::Spot);
    EXPECT_EQ(scene.lights[3].inner_cone, 0.25f);
    EXPECT_EQ(scene.lights[3].outer_cone, 0.5f);
    EXPECT_EQ(scene.lights[3].position, glm::vec3(0, 1, 0));
    EXPECT_NEAR(scene.lights[3].direction.x, -1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(scene.lights[3].direction), 1.0f, 1e-6f);
    ASSERT_TRUE(scene.has_camera);
    EXPECT_NEAR(scene.camera.vertical_fov_degrees, glm::degrees(0.5f), 1e-4f);
    EXPECT_EQ(scene.camera.position, glm::vec3(0, 0, 10));
}

// ---- The rest pose: what animations do not play, skins -----------------------------------------------------------

// A .glb of `document` and `bin` (the GLB container written here, independently of the loader's own repacking);
// `pad_json` false leaves the JSON chunk unpadded, as some exporters did.
std::string glb(const json& document, const std::string& bin, bool pad_json = true) {
    std::string text = document.dump();
    while (pad_json && text.size() % 4) text += ' ';
    std::string body = bin;
    while (body.size() % 4) body += '\0';
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    uint32_t total = uint32_t(12 + 8 + text.size() + (body.empty() ? 0 : 8 + body.size()));
    std::string out = "glTF" + u32(2) + u32(total) + u32(uint32_t(text.size())) + "JSON" + text;
    if (!body.empty()) out += u32(uint32_t(body.size())) + std::string("BIN\0", 4) + body;
    return out;
}

// An animation that targets a property through KHR_animation_pointer, with no node: valid glTF that tinygltf 2.7
// refuses. Prism does not play such channels, so the file loads, drawn as its nodes place it, with a warning.
json pointer_animation(int input, int output) {
    return {{{"channels",
              {{{"sampler", 0},
                {"target",
                 {{"path", "pointer"},
                  {"extensions", {{"KHR_animation_pointer", {{"pointer", "/nodes/0/translation"}}}}}}}}}},
             {"samplers", {{{"input", input}, {"output", output}}}}}};
}

TEST(LoadGltf, AnimationsWithoutATargetNodeLoadAsTheRestPose) {
    GltfBuilder gltf;
    int positions = triangle_positions(gltf);
    int times = gltf.view(std::vector<float>{0, 1});
    int input = gltf.accessor(
        {{"bufferView", times}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}, {"min", {0}}, {"max", {1}}});
    int moves = gltf.view(std::vector<float>{0, 0, 0, 5, 0, 0});
    int output = gltf.accessor({{"bufferView", moves}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    gltf.document["animations"] = pointer_animation(input, output);
    gltf.document["extensionsUsed"] = {"KHR_animation_pointer"};
    Scene scene = load(gltf.write("animation_pointer.gltf"));
    EXPECT_EQ(scene.triangle_count(), 1u);
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].transform, glm::mat4(1.0f));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("animation 'animation 0' is not played"), std::string::npos) << scene.warnings[0];
    EXPECT_FALSE(scene.animation.plays());
}

// In a .glb the JSON chunk is rewritten and the binary chunk kept: the same triangles as the file without.
TEST(LoadGltf, GlbWithAnimationsKeepsItsBinaryChunk) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 2, 0, 0, 0, 3, 0, 4, 4, 4});
    int indices = gltf.indices({0, 1, 2, 1, 3, 2});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}})}});
    json document = gltf.document;
    document["buffers"] = {{{"byteLength", gltf.buffer.size()}}};
    document["scenes"] = {{{"nodes", {0}}}};
    Scene plain = load(test::write_file("plain.glb", glb(document, gltf.buffer)));
    document["animations"] = pointer_animation(0, 0);
    Scene animated = load(test::write_file("animated.glb", glb(document, gltf.buffer)));
    ASSERT_EQ(plain.triangle_count(), 2u);
    ASSERT_EQ(animated.meshes.size(), 1u);
    EXPECT_EQ(animated.meshes[0].positions, plain.meshes[0].positions);
    EXPECT_EQ(animated.meshes[0].triangles, plain.meshes[0].triangles);
    EXPECT_EQ(animated.warnings.size(), plain.warnings.size() + 1);
}

// A JSON chunk not padded to 4 bytes (trimesh's old exporter) is read, with a warning; tinygltf alone refuses it.
TEST(LoadGltf, GlbWithUnpaddedJsonChunkLoadsWithAWarning) {
    GltfBuilder gltf;
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}}})}});
    json document = gltf.document;
    document["buffers"] = {{{"byteLength", gltf.buffer.size()}}};
    document["scenes"] = {{{"nodes", {0}}}};
    document["asset"]["generator"] = "x";
    while (document.dump().size() % 4 == 0)  // a JSON chunk that needs padding
        document["asset"]["generator"] = document["asset"]["generator"].get<std::string>() + "x";
    Scene scene = load(test::write_file("unpadded.glb", glb(document, gltf.buffer, false)));
    EXPECT_EQ(scene.triangle_count(), 1u);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("not padded to 4 bytes"), std::string::npos) << scene.warnings[0];
}

// An accessor without a bufferView is zeros (perhaps with sparse values): a small one loads even where the file's
// buffers (here 36 bytes of positions) could not hold it (48 bytes of colours).
TEST(LoadGltf, SmallAccessorWithoutBufferViewIsZeros) {
    GltfBuilder gltf;
    int positions = triangle_positions(gltf);
    int colors = gltf.accessor({{"componentType", 5126}, {"count", 3}, {"type", "VEC4"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}, {"COLOR_0", colors}}}}})}});
    Scene scene = load(gltf.write("zero_colors.gltf"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].colors, std::vector<glm::vec4>(3, glm::vec4(0.0f)));
}

// ---- Compressed meshes: Draco and meshopt ------------------------------------------------------------------------

// The real models the compressed files are made from: a glTF sample with normals and texture coordinates, and the
// Stanford bunny (a PLY scan, 69k triangles).
const Mesh& model_mesh(const std::string& file) {
    static std::map<std::string, Scene> loaded;
    auto [it, inserted] = loaded.try_emplace(file);
    if (inserted) it->second = load_scene(test::scene(file).string());
    return it->second.meshes.at(0);
}
const char* const kCompressionModels[] = {"gltf/Suzanne/Suzanne.gltf", "stanford/bunny.ply"};

glm::uvec3 smallest_corner_first(glm::uvec3 t) {
    if (t.y < t.x && t.y < t.z) return {t.y, t.z, t.x};
    if (t.z < t.x && t.z < t.y) return {t.z, t.x, t.y};
    return t;
}

// Each triangle as its three positions, starting at its smallest corner (winding kept), in sorted order: Draco's
// edgebreaker renumbers vertices and rotates corners, and the geometry must survive that unchanged.
std::vector<std::array<float, 9>> triangle_soup(const Mesh& mesh) {
    std::vector<std::array<float, 9>> soup;
    for (const glm::uvec3& t : mesh.triangles) {
        std::array<glm::vec3, 3> corners = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
        auto less = [](const glm::vec3& a, const glm::vec3& b) {
            return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
        };
        int first = less(corners[1], corners[0]) ? 1 : 0;
        if (less(corners[2], corners[first])) first = 2;
        std::array<float, 9> triangle;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) triangle[c * 3 + k] = corners[(first + c) % 3][k];
        soup.push_back(triangle);
    }
    std::sort(soup.begin(), soup.end());
    return soup;
}

TEST(LoadGltf, MeshoptCompressedModelsLoadExactly) {
    for (const char* file : kCompressionModels) {
        SCOPED_TRACE(file);
        const Mesh& original = model_mesh(file);
        Scene scene = load(test::write_file("meshopt.gltf", test::meshopt_gltf(test::plain_mesh(original)).embedded()));
        ASSERT_EQ(scene.meshes.size(), 1u);
        const Mesh& decoded = scene.meshes[0];
        EXPECT_EQ(decoded.positions, original.positions);
        EXPECT_EQ(decoded.normals, original.normals);
        EXPECT_EQ(decoded.uv0, original.uv0);
        // The index codec may rotate a triangle's corners (the winding stays).
        ASSERT_EQ(decoded.triangles.size(), original.triangles.size());
        size_t same = 0;
        for (size_t t = 0; t < decoded.triangles.size(); ++t)
            same += smallest_corner_first(decoded.triangles[t]) == smallest_corner_first(original.triangles[t]);
        EXPECT_EQ(same, decoded.triangles.size());
    }
}

// Normals as gltfpack stores them: 16-bit octahedral (the OCTAHEDRAL filter), normalized SHORT.
TEST(LoadGltf, MeshoptOctahedralNormalsDecodeToTheOriginalDirections) {
    const Mesh& original = model_mesh(kCompressionModels[0]);
    ASSERT_FALSE(original.normals.empty());
    Scene scene =
        load(test::write_file("meshopt-oct.gltf", test::meshopt_gltf(test::plain_mesh(original), true).embedded()));
    const Mesh& decoded = scene.meshes.at(0);
    ASSERT_EQ(decoded.normals.size(), original.normals.size());
    float worst = 0.0f;
    for (size_t i = 0; i < decoded.normals.size(); ++i)
        worst = std::max(worst, glm::length(decoded.normals[i] - glm::normalize(original.normals[i])));
    EXPECT_LT(worst, 1e-3f);
    EXPECT_EQ(decoded.positions, original.positions);
}

TEST(LoadGltf, DracoCompressedModelsKeepEveryTriangle) {
    for (const char* file : kCompressionModels) {
        SCOPED_TRACE(file);
        const Mesh& original = model_mesh(file);
        Scene scene = load(test::write_file("draco.gltf", test::draco_gltf(test::plain_mesh(original)).embedded()));
        ASSERT_EQ(scene.meshes.size(), 1u);
        const Mesh& decoded = scene.meshes[0];
        // Draco keeps the vertices the triangles use (the bunny's scan has a thousand that none does).
        EXPECT_LE(decoded.positions.size(), original.positions.size());
        EXPECT_EQ(decoded.normals.size(), original.normals.empty() ? 0u : decoded.positions.size());
        EXPECT_EQ(decoded.uv0.size(), original.uv0.empty() ? 0u : decoded.positions.size());
        EXPECT_TRUE(triangle_soup(decoded) == triangle_soup(original));
    }
}

// Quantized positions (Draco's usual setting): dequantized to within one step of the 14-bit grid over the bounds.
TEST(LoadGltf, DracoQuantizedPositionsDequantize) {
    const Mesh& original = model_mesh(kCompressionModels[1]);
    Scene scene = load(test::write_file("draco-q14.gltf", test::draco_gltf(test::plain_mesh(original), 14).embedded()));
    const Mesh& decoded = scene.meshes.at(0);
    ASSERT_EQ(decoded.triangles.size(), original.triangles.size());
    glm::vec3 low(INFINITY), high(-INFINITY), decoded_low(INFINITY), decoded_high(-INFINITY);
    for (const glm::vec3& p : original.positions) low = glm::min(low, p), high = glm::max(high, p);
    for (const glm::vec3& p : decoded.positions)
        decoded_low = glm::min(decoded_low, p), decoded_high = glm::max(decoded_high, p);
    const glm::vec3 extent = high - low;
    const float step = std::max(extent.x, std::max(extent.y, extent.z)) / float((1 << 14) - 1);
    for (int k = 0; k < 3; ++k) {
        EXPECT_LE(std::abs(decoded_low[k] - low[k]), step);
        EXPECT_LE(std::abs(decoded_high[k] - high[k]), step);
    }
}

// The Draco file with one change made to it, then written.
std::filesystem::path broken_draco(const std::string& name, const std::function<void(json&)>& change) {
    json gltf = json::parse(test::draco_gltf(test::plain_mesh(model_mesh(kCompressionModels[0]))).embedded());
    change(gltf);
    return test::write_file(name, gltf.dump());
}

std::filesystem::path broken_meshopt(const std::string& name, const std::function<void(json&)>& change) {
    json gltf = json::parse(test::meshopt_gltf(test::plain_mesh(model_mesh(kCompressionModels[0]))).embedded());
    change(gltf);
    return test::write_file(name, gltf.dump());
}

TEST(LoadGltf, BrokenDracoDataIsNamedInOneLine) {
    expect_error_naming_the_file(
        broken_draco(
            "draco-truncated.gltf",
            [](json& g) { g["bufferViews"][0]["byteLength"] = g["bufferViews"][0]["byteLength"].get<size_t>() / 2; }),
        "Draco data do not decode");
    expect_error_naming_the_file(
        broken_draco(
            "draco-id.gltf",
            [](json& g) {
                g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] =
                    7;
            }),
        "Draco attribute POSITION (id 7) is missing");
    expect_error_naming_the_file(
        broken_draco("draco-view.gltf",
                     [](json& g) {
                         g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 9;
                     }),
        "names no bufferView that exists");
    expect_error_naming_the_file(
        broken_draco("draco-past-end.gltf", [](json& g) { g["bufferViews"][0]["byteOffset"] = 64; }),
        "Draco data lie past the end of buffer 0");
    expect_error_naming_the_file(
        broken_draco("draco-strip.gltf", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = 5; }),
        "a Draco mesh is a triangle list");
}

TEST(LoadGltf, BrokenMeshoptDataIsNamedInOneLine) {
    auto extension = [](json& g, int view) -> json& {
        return g["bufferViews"][view]["extensions"]["EXT_meshopt_compression"];
    };
    // 2^31 vertices claimed from a few hundred bytes: refused before anything that size is allocated.
    expect_error_naming_the_file(broken_meshopt("meshopt-count.gltf",
                                                [&](json& g) {
                                                    extension(g, 0)["count"] = 2147483647;
                                                    g["accessors"][0]["count"] = 2147483647;
                                                }),
                                 "more than the codec can produce");
    expect_error_naming_the_file(
        broken_meshopt(
            "meshopt-short.gltf",
            [&](json& g) { extension(g, 0)["byteLength"] = extension(g, 0)["byteLength"].get<size_t>() / 2; }),
        "ATTRIBUTES data do not decode");
    expect_error_naming_the_file(
        broken_meshopt("meshopt-stride.gltf", [&](json& g) { extension(g, 0)["byteStride"] = 6; }),
        "must be a multiple of 4");
    expect_error_naming_the_file(
        broken_meshopt("meshopt-mode.gltf", [&](json& g) { extension(g, 0)["mode"] = "VERTICES"; }),
        "unknown mode \"VERTICES\"");
    expect_error_naming_the_file(
        broken_meshopt("meshopt-filter.gltf",
                       [&](json& g) { extension(g, int(g["bufferViews"].size()) - 1)["filter"] = "OCTAHEDRAL"; }),
        "filter OCTAHEDRAL does not apply to mode TRIANGLES");
    expect_error_naming_the_file(
        broken_meshopt("meshopt-source.gltf", [&](json& g) { extension(g, 0)["byteOffset"] = 1 << 30; }),
        "compressed bytes lie past the end of buffer 0");
    // An accessor that reads the fallback buffer directly, through a view that is not compressed.
    expect_error_naming_the_file(
        broken_meshopt("meshopt-fallback.gltf", [&](json& g) { g["bufferViews"][0].erase("extensions"); }),
        "the meshopt fallback buffer 1, which holds no data");
    // A fallback flag that is not the boolean true does not make a fallback (the fuzzer found a number raising
    // nlohmann's type_error there): the buffer without a uri is then refused, naming the file.
    for (const json& flag : {json(1), json("true"), json(nullptr)}) {
        SCOPED_TRACE(flag.dump());
        expect_error_naming_the_file(
            broken_meshopt(
                "meshopt-fallback-flag.gltf",
                [&](json& g) { g["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"] = flag; }),
            "a buffer or image without a uri");
    }
}

// ---- Malformed input -------------------------------------------------------------------------------------------

// A .gltf's buffer must name its data (only a .glb's first buffer may leave the uri out, for its binary chunk).
TEST(LoadGltf, BufferWithoutUriNamesTheFile) {
    GltfBuilder gltf;
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}}})}});
    gltf.document["buffers"] = {{{"byteLength", gltf.buffer.size()}}};
    expect_error_naming_the_file(gltf.write("buffer_without_uri.gltf", false), "a buffer or image without a uri");
}

// A buffer whose uri names a folder, or holds a NUL once percent-decoded (tinygltf's regression file issue-416), is
// refused in one line that starts with the glTF's name, not with the folder's.
TEST(LoadGltf, BufferUriNamingAFolderOrHoldingNulNamesTheFile) {
    std::filesystem::create_directories(test::temp_dir("files") / "a_folder");  // beside what write_file writes
    for (const char* uri : {"a_folder", "x%00y.bin"}) {
        SCOPED_TRACE(uri);
        GltfBuilder gltf;
        gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}}})}});
        gltf.document["buffers"] = {{{"byteLength", gltf.buffer.size()}, {"uri", uri}}};
        expect_error_naming_the_file(gltf.write("buffer_uri.gltf", false),
                                     std::string(uri) == "a_folder" ? "is a directory" : "NUL");
    }
}

// A large accessor without a bufferView in a file whose buffers could not hold it is refused before its zeros are
// allocated (bounded memory for a few bytes of hostile JSON).
TEST(LoadGltf, HugeAccessorWithoutBufferViewIsAnError) {
    GltfBuilder gltf;
    int positions = gltf.accessor({{"componentType", 5126}, {"count", 400000000}, {"type", "VEC3"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    expect_error_naming_the_file(gltf.write("huge_zeros.gltf"), "without a bufferView is more than");
}

TEST(LoadGltf, OutOfRangeIndexIsAnError) {
    GltfBuilder gltf;
    int positions = triangle_positions(gltf), indices = gltf.indices({0, 1, 7});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}})}});
    expect_error_naming_the_file(gltf.write("bad_index.gltf"), "index 7 out of range");
}

TEST(LoadGltf, AccessorPastTheBufferIsAnError) {
    GltfBuilder gltf;
    int view = gltf.view(std::vector<float>{0, 0, 0, 1, 0, 0});
    int positions = gltf.accessor({{"bufferView", view}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    std::string message = error_message(gltf.write("short_buffer.gltf"));
    EXPECT_NE(message.find("accessor 0"), std::string::npos) << message;
    EXPECT_NE(message.find("past the end"), std::string::npos) << message;
}

TEST(LoadGltf, MissingBufferFileIsAnError) {
    GltfBuilder gltf;
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}}})}});
    gltf.document["buffers"] = {{{"byteLength", gltf.buffer.size()}, {"uri", "no_such_buffer.bin"}}};
    expect_error_naming_the_file(gltf.write("missing_buffer.gltf", false), "no_such_buffer.bin");
}

TEST(LoadGltf, MissingImageFileNamesTheUri) {
    GltfBuilder gltf;
    gltf.document["images"] = {{{"uri", "no_such_texture.png"}}};
    gltf.document["textures"] = {{{"source", 0}}};
    gltf.document["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}, {"material", 0}}})}});
    expect_error_naming_the_file(gltf.write("missing_image.gltf"), "no_such_texture.png");
}

// EXT_texture_webp as gltf-transform writes it: the texture's image is a WebP file; a `source` beside it is a PNG
// fallback for viewers without WebP, and Prism, reading WebP, takes the WebP image (as the extension asks).
TEST(LoadGltf, WebpTexturesAreReadAndPreferredToTheFallback) {
    auto one_pixel_file = [](const std::string& name, uint32_t rgba, bool webp) {
        std::filesystem::path path = test::temp_dir("files") / name;
        if (!webp) {
            write_png(path, 1, 1, std::vector<uint32_t>{rgba});
            return path;
        }
        uint8_t* encoded = nullptr;
        const size_t size = WebPEncodeLosslessRGBA(reinterpret_cast<const uint8_t*>(&rgba), 1, 1, 4, &encoded);
        test::write_file(name, std::string(reinterpret_cast<const char*>(encoded), size));
        WebPFree(encoded);
        return path;
    };
    one_pixel_file("red.webp", 0xff0000ffu, true);
    one_pixel_file("green.png", 0xff00ff00u, false);
    for (bool with_fallback : {false, true}) {
        SCOPED_TRACE(with_fallback);
        GltfBuilder gltf;
        gltf.document["images"] = {{{"uri", "red.webp"}, {"mimeType", "image/webp"}}, {{"uri", "green.png"}}};
        json texture = {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}};
        if (with_fallback) texture["source"] = 1;
        gltf.document["textures"] = json::array({texture});
        gltf.document["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
        gltf.document["extensionsUsed"] = {"EXT_texture_webp"};
        if (!with_fallback) gltf.document["extensionsRequired"] = {"EXT_texture_webp"};
        gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", triangle_positions(gltf)}}}, {"material", 0}}})}});
        Scene scene = load(gltf.write("webp.gltf"));
        ASSERT_EQ(scene.textures.size(), 1u);
        EXPECT_EQ(scene.textures[0].texels, std::vector<uint32_t>{0xff0000ffu});
        ASSERT_EQ(scene.materials.size(), 1u);
        EXPECT_EQ(scene.materials[0].textures.size(), 1u);
        EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    }
}

TEST(LoadGltf, NodeCycleIsAnError) {
    GltfBuilder gltf;
    gltf.node({{"children", {1}}});
    gltf.node({{"children", {0}}});
    gltf.document["scenes"] = {{{"nodes", {0}}}};
    std::string message = error_message(gltf.write("cycle.gltf"));
    EXPECT_NE(message.find("its own ancestor"), std::string::npos) << message;
}

TEST(LoadGltf, TruncatedGlbIsAnError) {
    std::string box = read_bytes(test::scene("gltf/Box/Box.glb"));
    ASSERT_GT(box.size(), 100u);
    for (size_t length : {size_t(0), size_t(11), size_t(20), size_t(40), box.size() / 2, box.size() - 1}) {
        SCOPED_TRACE(length);
        expect_error_naming_the_file(test::write_file("truncated.glb", box.substr(0, length)), "");
    }
}

TEST(LoadGltf, RandomBytesAreAnError) {
    std::mt19937 random(7);
    std::string noise(4096, '\0');
    for (char& c : noise) c = static_cast<char>(random());
    for (const char* name : {"noise.glb", "noise.gltf"})
        expect_error_naming_the_file(test::write_file(name, noise), "");
    // Valid JSON that is not glTF.
    expect_error_naming_the_file(test::write_file("not_gltf.gltf", "{\"hello\": [1, 2, 3]}"), "");
}

}  // namespace
}  // namespace prism
