// EXT_mesh_gpu_instancing becomes instances of one mesh (no copies). Skins: test_gltf_skin.cpp; morph targets:
// test_gltf_morph.cpp.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/loaders/load_gltf.h"
#include "tests/gltf_builder.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// One triangle mesh, drawn by a node with 5 x 5 x 5 translated (and, for half of them, scaled) instances.
std::filesystem::path instanced_grid(const std::string& name) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0});
    std::vector<float> translations, scales;
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 5; ++x) {
                translations.insert(translations.end(), {float(x), float(y), float(z)});
                float s = (x + y + z) % 2 ? 1.0f : 0.5f;
                scales.insert(scales.end(), {s, s, s});
            }
    int translation = gltf.positions(translations);
    int scale = gltf.positions(scales);
    int mesh = gltf.mesh(json::array({{{"attributes", {{"POSITION", positions}}}}}));
    gltf.node({{"mesh", mesh},
               {"translation", {10, 0, 0}},
               {"extensions",
                {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}, {"SCALE", scale}}}}}}}});
    gltf.document["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    gltf.document["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
    return gltf.write(name);
}

}  // namespace

TEST(GltfInstancing, EveryGpuInstanceIsAnInstanceOfOneMesh) {
    Scene scene;
    load_gltf(instanced_grid("instanced.gltf"), scene);
    ASSERT_EQ(scene.instances.size(), 125u);
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.triangle_count(), 125u);
    for (const std::string& warning : scene.warnings) ADD_FAILURE() << warning;
    // Instance (x, y, z) sits at the node's translation plus its own, scaled by its own scale.
    const Instance& last = scene.instances.back();
    EXPECT_EQ(glm::vec3(last.transform[3]), glm::vec3(14.0f, 4.0f, 4.0f));
    EXPECT_FLOAT_EQ(last.transform[0][0], 0.5f);  // 4 + 4 + 4 is even: scale 0.5
    EXPECT_FLOAT_EQ(scene.instances[1].transform[0][0], 1.0f);
}

TEST(GltfInstancing, PrismInfoCountsTheInstances) {
    test::CommandResult info =
        test::run_prism("info --scene " + instanced_grid("instanced_info.gltf").string() + " --json");
    ASSERT_EQ(info.exit_code, 0) << info.output;
    json parsed = json::parse(info.output.substr(info.output.find('{')));
    EXPECT_EQ(parsed["scene"]["instances"], 125);
    EXPECT_EQ(parsed["scene"]["meshes"], 1);
}

TEST(GltfInstancing, MismatchedAttributeCountsAreAnError) {
    GltfBuilder gltf;
    int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    int translation = gltf.positions({0, 0, 0, 1, 1, 1});
    int scale = gltf.positions({1, 1, 1, 1, 1, 1, 2, 2, 2});
    gltf.node({{"mesh", gltf.mesh(json::array({{{"attributes", {{"POSITION", positions}}}}}))},
               {"extensions",
                {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", translation}, {"SCALE", scale}}}}}}}});
    std::filesystem::path file = gltf.write("instancing_counts.gltf");
    std::string message = test::error_message([&] {
        Scene scene;
        load_gltf(file, scene);
    });
    EXPECT_NE(message.find("instancing_counts.gltf"), std::string::npos) << message;
    EXPECT_NE(message.find("attribute counts differ"), std::string::npos) << message;
}

}  // namespace prism
