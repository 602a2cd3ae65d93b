// glTF skins are applied at load, in the pose the file's nodes give the joints (core/loaders/gltf_skin.h): linear
// blend skinning into world space, the skinned node's own transform ignored, one copy per (mesh, primitive, skin).
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "core/loaders/load_gltf.h"
#include "tests/gltf_builder.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

void expect_near(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

// A strip of two triangles from y = 0 to y = 2, its bottom pair of vertices on joint 0 at the origin, its top pair
// on joint 1, bound at (0, 1, 0) and posed there turned 90 degrees about z; the mesh node sits at x = 10, which the
// spec says a skinned node ignores. Joint 1's inverse bind matrix undoes its bind translation.
struct SkinnedStrip {
    GltfBuilder gltf;
    json joints_accessor, weights_accessor;

    SkinnedStrip() {
        int positions = gltf.positions({-0.5f, 0, 0, 0.5f, 0, 0, -0.5f, 2, 0, 0.5f, 2, 0});
        int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
        int indices = gltf.indices({0, 1, 2, 1, 3, 2});
        std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        joints_accessor = {{"bufferView", gltf.view(joints)}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}};
        weights_accessor = {
            {"bufferView", gltf.view(weights)}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}};
        int joints_index = gltf.accessor(joints_accessor);
        int weights_index = gltf.accessor(weights_accessor);
        std::vector<float> inverse_bind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,  0, 1,
                                           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
        int ibm = gltf.accessor(
            {{"bufferView", gltf.view(inverse_bind)}, {"componentType", 5126}, {"count", 2}, {"type", "MAT4"}});
        int mesh = gltf.mesh({{{"attributes",
                                {{"POSITION", positions},
                                 {"NORMAL", normals},
                                 {"JOINTS_0", joints_index},
                                 {"WEIGHTS_0", weights_index}}},
                               {"indices", indices}}});
        const float s = std::sqrt(0.5f);
        gltf.node({{"name", "root joint"}, {"children", {1}}});                                      // 0
        gltf.node({{"name", "tip joint"}, {"translation", {0, 1, 0}}, {"rotation", {0, 0, s, s}}});  // 1
        gltf.node({{"name", "strip"}, {"mesh", mesh}, {"skin", 0}, {"translation", {10, 0, 0}}});    // 2
        gltf.document["skins"] = {{{"joints", {0, 1}}, {"inverseBindMatrices", ibm}}};
    }
};

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_gltf(path, scene);
    return scene;
}

TEST(GltfSkin, VerticesFollowTheirJointsInWorldSpace) {
    SkinnedStrip strip;
    Scene scene = load(strip.gltf.write("skinned_strip.gltf"));
    ASSERT_EQ(scene.instances.size(), 1u);
    const Instance& instance = scene.instances[0];
    EXPECT_EQ(instance.transform, glm::mat4(1.0f))
        << "skinned vertices are in world space; the node's x = 10 is ignored";
    const Mesh& mesh = scene.meshes[instance.mesh];
    ASSERT_EQ(mesh.positions.size(), 4u);
    expect_near(mesh.positions[0], {-0.5f, 0, 0});  // joint 0: where it was bound
    expect_near(mesh.positions[1], {0.5f, 0, 0});
    // Joint 1 turns the top about (0, 1, 0): (x, 2) -> (-1, 1 + x).
    expect_near(mesh.positions[2], {-1, 0.5f, 0});
    expect_near(mesh.positions[3], {-1, 1.5f, 0});
    expect_near(mesh.normals[2], {0, 0, 1});  // a turn about z keeps the normal
    for (const std::string& warning : scene.warnings)
        EXPECT_EQ(warning.find("skin"), std::string::npos) << "nothing to warn about: " << warning;
}

TEST(GltfSkin, WeightsBlendTheJointsAndAreNormalized) {
    SkinnedStrip strip;
    // The top vertices half on each joint, with weights that sum to 2: normalized to a half each.
    std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
    std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0};
    strip.gltf.document["accessors"][strip.gltf.document["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"]
                                         .get<int>()]["bufferView"] = strip.gltf.view(joints);
    strip.gltf.document["accessors"][strip.gltf.document["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"]
                                         .get<int>()]["bufferView"] = strip.gltf.view(weights);
    Scene scene = load(strip.gltf.write("blended_strip.gltf"));
    const Mesh& mesh = scene.meshes[scene.instances[0].mesh];
    // The mean of (0.5, 2) (joint 0) and (-1, 1.5) (joint 1).
    expect_near(mesh.positions[3], {-0.25f, 1.75f, 0});
}

TEST(GltfSkin, TheSameMeshAndSkinAreOneCopyForEveryNode) {
    SkinnedStrip strip;
    strip.gltf.node({{"name", "strip again"}, {"mesh", 0}, {"skin", 0}, {"translation", {20, 0, 0}}});
    Scene scene = load(strip.gltf.write("two_strips.gltf"));
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.instances[0].mesh, scene.instances[1].mesh);
    EXPECT_EQ(scene.meshes.size(), 1u);
}

// Without inverseBindMatrices every joint's is the identity (the spec's default; tinygltf 2.7 asked for them).
TEST(GltfSkin, MissingInverseBindMatricesAreIdentities) {
    SkinnedStrip strip;
    strip.gltf.document["skins"][0].erase("inverseBindMatrices");
    Scene scene = load(strip.gltf.write("strip_without_ibm.gltf"));
    const Mesh& mesh = scene.meshes[scene.instances[0].mesh];
    // Joint 1's whole world transform applies: turned, then moved up by 1. (x, 2) -> (-2, 1 + x).
    expect_near(mesh.positions[3], {-2, 1.5f, 0});
}

// A skinned node whose primitive has no joints and weights is drawn where its node puts it, with one warning.
TEST(GltfSkin, APrimitiveWithoutJointsIsDrawnUnskinnedWithAWarning) {
    SkinnedStrip strip;
    strip.gltf.document["meshes"][0]["primitives"][0]["attributes"].erase("JOINTS_0");
    Scene scene = load(strip.gltf.write("strip_without_joints.gltf"));
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].transform[3], glm::vec4(10, 0, 0, 1));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("strip_without_joints.gltf: mesh 0 primitive 0 belongs to a skinned node but "
                                     "has no JOINTS_0 and WEIGHTS_0"),
              std::string::npos)
        << scene.warnings[0];
}

// A thousand JOINTS_n / WEIGHTS_n sets naming one 10,000-vertex accessor would copy 80M floats from a file of
// 160 KB: the load stops in one line before reading them.
TEST(GltfSkin, InfluenceSetsSharingOneAccessorStayWithinABudget) {
    SkinnedStrip strip;
    std::vector<float> weights(4 * 10000, 0.0f);
    const int many = strip.gltf.accessor(
        {{"bufferView", strip.gltf.view(weights)}, {"componentType", 5126}, {"count", 10000}, {"type", "VEC4"}});
    json& attributes = strip.gltf.document["meshes"][0]["primitives"][0]["attributes"];
    for (int set = 1; set < 1000; ++set) {
        attributes["JOINTS_" + std::to_string(set)] = many;
        attributes["WEIGHTS_" + std::to_string(set)] = many;
    }
    const std::filesystem::path file = strip.gltf.write("influence-sets.gltf");
    const std::string message = test::error_message([&] { (void)load(file); });
    EXPECT_NE(message.find("its JOINTS_n and WEIGHTS_n sets would copy more than 16777216 floats"), std::string::npos)
        << message;
}

// Malformed skins: one line naming the file and the cause, nothing drawn half-skinned.
TEST(GltfSkin, MalformedSkinsAreOneLineErrors) {
    auto expect_error = [](SkinnedStrip& strip, const std::string& name, const std::string& what) {
        std::filesystem::path file = strip.gltf.write(name);
        std::string message = test::error_message([&] { (void)load(file); });
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(what), std::string::npos) << message;
    };
    {
        SkinnedStrip strip;
        std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 1, 0, 0, 0};
        strip.gltf.document["accessors"][3]["bufferView"] = strip.gltf.view(joints);
        expect_error(strip, "skin_joint_out_of_range.gltf", "vertex 2 names joint 7");
    }
    {
        SkinnedStrip strip;
        std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, -1, 0, 0, 0, NAN, 0, 0, 0};
        strip.gltf.document["accessors"][4]["bufferView"] = strip.gltf.view(weights);
        expect_error(strip, "skin_negative_weight.gltf", "vertex 2 has a weight that is negative or not a number");
    }
    {
        SkinnedStrip strip;
        strip.gltf.document["skins"][0]["joints"] = {0, 99};
        expect_error(strip, "skin_joint_not_a_node.gltf", "skin 0: joint 99 is not a node");
    }
    {
        SkinnedStrip strip;
        strip.gltf.document["nodes"][2]["skin"] = 3;
        expect_error(strip, "skin_does_not_exist.gltf", "node 2: skin 3 does not exist");
    }
    {
        SkinnedStrip strip;
        strip.gltf.document["skins"][0]["joints"] = json::array();
        expect_error(strip, "skin_without_joints.gltf", "skin 0: \"joints\" must be a non-empty array");
    }
    {
        SkinnedStrip strip;
        strip.gltf.document["accessors"][5]["count"] = 1;
        expect_error(strip, "skin_too_few_matrices.gltf", "1 inverse bind matrices for 2 joints");
    }
    {
        SkinnedStrip strip;
        strip.gltf.document["accessors"][5]["type"] = "VEC4";
        expect_error(strip, "skin_matrices_not_mat4.gltf", "must be MAT4 of floats");
    }
}

}  // namespace
}  // namespace prism
