// glTF morph targets are applied at load with the weights the file gives them (core/loaders/gltf_morph.h): the
// node's own "weights", else the mesh's defaults; one copy per weight set, the mesh's shared by every node.
#include <cmath>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/loaders/load_gltf.h"
#include "tests/gltf_builder.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// One triangle with one morph target that moves every vertex by +1 in z and turns its normals from +z to +x.
struct MorphingTriangle {
    GltfBuilder gltf;

    explicit MorphingTriangle(json mesh_weights) {
        int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
        int position_offsets = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1});
        int normal_offsets = gltf.positions({1, 0, -1, 1, 0, -1, 1, 0, -1});
        json mesh = {{"primitives",
                      {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                        {"targets", {{{"POSITION", position_offsets}, {"NORMAL", normal_offsets}}}}}}}};
        if (!mesh_weights.is_null()) mesh["weights"] = mesh_weights;
        gltf.document["meshes"].push_back(mesh);
    }
};

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_gltf(path, scene);
    return scene;
}

TEST(GltfMorph, TheMeshsDefaultWeightsApplyAndAreSharedByItsNodes) {
    MorphingTriangle morph(json::array({0.5}));
    morph.gltf.node({{"mesh", 0}});
    morph.gltf.node({{"mesh", 0}, {"translation", {4, 0, 0}}});
    Scene scene = load(morph.gltf.write("morph_defaults.gltf"));
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.instances[0].mesh, scene.instances[1].mesh) << "one copy for the mesh's own weights";
    const Mesh& mesh = scene.meshes[scene.instances[0].mesh];
    EXPECT_EQ(mesh.positions[1], glm::vec3(1, 0, 0.5f));
    EXPECT_NEAR(mesh.normals[0].x, 0.5f / std::sqrt(0.5f), 1e-6f);  // (0.5, 0, 0.5), normalized
    EXPECT_NEAR(glm::length(mesh.normals[0]), 1.0f, 1e-6f);
    for (const std::string& warning : scene.warnings)
        EXPECT_EQ(warning.find("morph"), std::string::npos) << "nothing to warn about: " << warning;
}

TEST(GltfMorph, ANodesOwnWeightsGiveItsOwnCopy) {
    MorphingTriangle morph(json::array({0.5}));
    morph.gltf.node({{"mesh", 0}});
    morph.gltf.node({{"mesh", 0}, {"weights", {1.0}}});
    morph.gltf.node({{"mesh", 0}, {"weights", {0.5}}});  // the mesh's own: shares its copy
    Scene scene = load(morph.gltf.write("morph_node_weights.gltf"));
    ASSERT_EQ(scene.instances.size(), 3u);
    EXPECT_NE(scene.instances[0].mesh, scene.instances[1].mesh);
    EXPECT_EQ(scene.instances[0].mesh, scene.instances[2].mesh);
    EXPECT_EQ(scene.meshes[scene.instances[1].mesh].positions[2], glm::vec3(0, 1, 1));
    EXPECT_EQ(scene.meshes[scene.instances[0].mesh].positions[2], glm::vec3(0, 1, 0.5f));
}

TEST(GltfMorph, WithoutWeightsTheMeshIsAsStored) {
    MorphingTriangle morph(nullptr);
    morph.gltf.node({{"mesh", 0}});
    Scene scene = load(morph.gltf.write("morph_no_weights.gltf"));
    EXPECT_EQ(scene.meshes[scene.instances[0].mesh].positions[1], glm::vec3(1, 0, 0));
}

// Weights on 2,000 targets that share one 20,000-vertex displacement accessor: the targets are added one at a time
// as they are read (all at once they would hold 480 MB; the morph tests alone peak at about 20 MB), to the same sum.
TEST(GltfMorph, ManyTargetsSharingOneAccessorAreAddedOneAtATime) {
    GltfBuilder gltf;
    std::vector<float> xyz, lift;
    for (int v = 0; v < 20000; ++v) {
        xyz.insert(xyz.end(), {float(v % 100), float(v / 100), 0.0f});
        lift.insert(lift.end(), {0.0f, 0.0f, 1.0f});
    }
    const int positions = gltf.positions(xyz);
    const int offsets = gltf.positions(lift);
    json targets = json::array();
    for (int t = 0; t < 2000; ++t) targets.push_back({{"POSITION", offsets}});
    gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"targets", targets}}});
    gltf.document["meshes"][0]["weights"] = std::vector<double>(2000, 0.0005);
    gltf.node({{"mesh", 0}});
    const Scene scene = load(gltf.write("many-shared-targets.gltf"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_NEAR(scene.meshes[0].positions[12345].z, 1.0f, 1e-3f);  // 2,000 x 0.0005 of a lift of 1
}

TEST(GltfMorph, MalformedTargetsAndWeightsAreOneLineErrors) {
    auto expect_error = [](const std::filesystem::path& file, const std::string& what) {
        std::string message = test::error_message([&] { (void)load(file); });
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    {
        MorphingTriangle morph(json::array({1e39}));  // no float holds it
        morph.gltf.node({{"mesh", 0}});
        expect_error(morph.gltf.write("morph_huge_weight.gltf"),
                     "mesh 0 primitive 0: morph target 0 has a weight that is not a number");
    }
    {
        MorphingTriangle morph(json::array({1.0}));
        morph.gltf.document["accessors"][2]["count"] = 2;
        morph.gltf.node({{"mesh", 0}});
        expect_error(morph.gltf.write("morph_short_target.gltf"),
                     "morph target 0 POSITION must be VEC3 and as long as POSITION");
    }
}

}  // namespace
}  // namespace prism
