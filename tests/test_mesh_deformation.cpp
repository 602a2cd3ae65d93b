// Meshes an animation deforms (core/scene/mesh_deformation.h): skins whose joints a glTF animation moves and morph
// targets whose weights it keys, posed anew for every frame, their BVHs refitted in place
// (core/render/device_scene.h, update_mesh_vertices) and uploaded (RenderEngine::move_to).
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "core/loaders/load_gltf.h"
#include "core/loaders/scene_loader.h"
#include "core/render/device_scene.h"
#include "core/render/render_engine.h"
#include "core/scene/node_animation.h"
#include "core/scene/scene_motion.h"
#include "tests/gltf_builder.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

void expect_near(glm::vec3 actual, glm::vec3 expected, float tolerance = 1e-5f) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
}

// A float SCALAR (or wider) accessor over `values`.
int float_accessor(GltfBuilder& gltf, const std::vector<float>& values, const char* type, int count) {
    return gltf.accessor(
        {{"bufferView", gltf.view(values)}, {"componentType", 5126}, {"count", count}, {"type", type}});
}

// A strip of two triangles from y = 0 to y = 2: its bottom vertices on joint 0 at the origin, its top ones on
// joint 1 at (0, 1, 0), which the animation turns about z from 0 to 90 degrees over one second (LINEAR).
struct BendingStrip {
    GltfBuilder gltf;
    std::filesystem::path file;

    explicit BendingStrip(const std::string& name) {
        const int positions = gltf.positions({-0.5f, 0, 0, 0.5f, 0, 0, -0.5f, 2, 0, 0.5f, 2, 0});
        const int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
        const int indices = gltf.indices({0, 1, 2, 1, 3, 2});
        const std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
        const int joints_index =
            gltf.accessor({{"bufferView", gltf.view(joints)}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}});
        const int weights_index = float_accessor(gltf, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
        const int ibm = float_accessor(
            gltf, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1},
            "MAT4", 2);
        const int mesh = gltf.mesh({{{"attributes",
                                      {{"POSITION", positions},
                                       {"NORMAL", normals},
                                       {"JOINTS_0", joints_index},
                                       {"WEIGHTS_0", weights_index}}},
                                     {"indices", indices}}});
        gltf.node({{"name", "root joint"}, {"children", {1}}});          // 0
        gltf.node({{"name", "tip joint"}, {"translation", {0, 1, 0}}});  // 1
        gltf.node({{"name", "strip"}, {"mesh", mesh}, {"skin", 0}});     // 2
        gltf.document["skins"] = {{{"joints", {0, 1}}, {"inverseBindMatrices", ibm}}};
        const float s = std::sqrt(0.5f);
        const int input = float_accessor(gltf, {0, 1}, "SCALAR", 2);
        const int output = float_accessor(gltf, {0, 0, 0, 1, 0, 0, s, s}, "VEC4", 2);
        gltf.document["animations"] = {
            {{"name", "bend"},
             {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "rotation"}}}}}},
             {"samplers", {{{"input", input}, {"output", output}}}}}};
        file = gltf.write(name);
    }
};

// One triangle whose target lifts its third vertex by 1 in y; the weights channel keys that target from 0 to 1 over
// one second on node 0. Node 1 draws the same mesh unanimated, 5 to the right.
struct MorphingTriangle {
    GltfBuilder gltf;
    std::filesystem::path file;

    explicit MorphingTriangle(const std::string& name, std::vector<float> keyed = {0, 1}) {
        const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        const int lift = gltf.positions({0, 0, 0, 0, 0, 0, 0, 1, 0});
        const int mesh = gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"targets", {{{"POSITION", lift}}}}}});
        gltf.document["meshes"][0]["weights"] = {0.0};
        gltf.node({{"name", "morphing"}, {"mesh", mesh}});
        gltf.node({{"name", "still"}, {"mesh", mesh}, {"translation", {5, 0, 0}}});
        const int input = float_accessor(gltf, {0, 1}, "SCALAR", 2);
        const int output = float_accessor(gltf, keyed, "SCALAR", int(keyed.size()));
        gltf.document["animations"] = {
            {{"name", "lift"},
             {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}},
             {"samplers", {{{"input", input}, {"output", output}}}}}};
        file = gltf.write(name);
    }
};

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_gltf(path, scene);
    return scene;
}

TEST(MeshDeformation, MorphTargetsAddTheirWeightedDisplacements) {
    DeformedVertices vertices{{{0, 0, 0}, {1, 0, 0}}, {{0, 0, 1}, {0, 0, 1}}, {}};
    std::vector<MorphTarget> targets(2);
    targets[0].positions = {{0, 2, 0}, {0, 0, 0}};
    targets[0].normals = {{1, 0, 0}, {0, 0, 0}};
    targets[1].positions = {{0, 0, 0}, {4, 0, 0}};
    morph_vertices(vertices, targets, std::vector<float>{0.5f, 0.25f});
    expect_near(vertices.positions[0], {0, 1, 0});
    expect_near(vertices.positions[1], {2, 0, 0});
    expect_near(vertices.normals[0], glm::normalize(glm::vec3(0.5f, 0, 1)));  // moved normals are normalized
    expect_near(vertices.normals[1], {0, 0, 1});
    // Weights past the targets are ignored, missing ones are 0.
    DeformedVertices again{{{0, 0, 0}, {1, 0, 0}}, {}, {}};
    morph_vertices(again, targets, std::vector<float>{1.0f});
    expect_near(again.positions[0], {0, 2, 0});
    expect_near(again.positions[1], {1, 0, 0});
}

// Linear blend skinning: the blend of the joints' matrices, divided by the weights' sum; normals by its inverse
// transpose; a vertex with no weight stays.
TEST(MeshDeformation, SkinsBlendTheirJointsMatrices) {
    DeformedVertices vertices{{{1, 1, 0}, {1, 1, 0}, {1, 1, 0}}, {{1, 1, 0}, {1, 1, 0}, {1, 1, 0}}, {}};
    SkinInfluences influences;
    influences.per_vertex = 2;
    influences.joints = {0, 1, 1, 0, 0, 1};
    influences.weights = {2, 2, 1, 0, 0, 0};
    const std::vector<glm::mat4> joints = {glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)),
                                           glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1))};
    skin_vertices(vertices, influences, joints);
    expect_near(vertices.positions[0], {6.5f, 1, 0});  // halfway: (11, 1, 0) and (2, 1, 0)
    expect_near(vertices.positions[1], {2, 1, 0});
    expect_near(vertices.positions[2], {1, 1, 0});  // no weight
    // A normal under x scaled by 2 tilts away from x: the inverse transpose scales it by (1/2, 1, 1).
    expect_near(vertices.normals[1], glm::normalize(glm::vec3(0.5f, 1, 0)));
    expect_near(vertices.normals[2], {1, 1, 0});
}

TEST(MeshDeformation, WeightChannelsSampleEveryWeight) {
    WeightChannel channel;
    channel.width = 2;
    channel.times = {1.0f, 3.0f};
    channel.values = {0, 1, 4, -1};
    EXPECT_EQ(sample_weights(channel, 0.0f), (std::vector<float>{0, 1}));  // held before the first key
    EXPECT_EQ(sample_weights(channel, 2.0f), (std::vector<float>{2, 0}));
    EXPECT_EQ(sample_weights(channel, 5.0f), (std::vector<float>{4, -1}));
    channel.interpolation = AnimationInterpolation::Step;
    EXPECT_EQ(sample_weights(channel, 2.9f), (std::vector<float>{0, 1}));
    // CUBICSPLINE: in-tangents, values, out-tangents per key; with zero tangents, smoothstep between the values.
    channel.interpolation = AnimationInterpolation::CubicSpline;
    channel.values = {0, 0, 0, 1, 0, 0, 0, 0, 8, 1, 0, 0};
    const std::vector<float> quarter = sample_weights(channel, 1.5f);
    const float u = 0.25f, smooth = 3 * u * u - 2 * u * u * u;
    EXPECT_NEAR(quarter[0], 8 * smooth, 1e-5f);
    EXPECT_NEAR(quarter[1], 1.0f, 1e-5f);
}

// The loader keeps the skin of a mesh whose joints move, and a sequence poses it at every moment; a still render
// keeps the file's pose.
TEST(MeshDeformation, MovingJointsPoseTheSkinAtEveryMoment) {
    BendingStrip strip("bending-strip.gltf");
    const Scene scene = load(strip.file);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_TRUE(scene.animation.plays());
    ASSERT_EQ(scene.animation.deformations.size(), 1u);
    EXPECT_TRUE(scene.animation.instances.empty());
    const uint32_t mesh = scene.animation.deformations[0].mesh;
    expect_near(scene.meshes[mesh].positions[2], {-0.5f, 2, 0});  // the file's pose
    const std::vector<DeformedVertices> half = deformed_meshes_at(scene.animation, 0.5);
    ASSERT_EQ(half.size(), 1u);
    // The top vertices turn 45 degrees about (0, 1, 0); the bottom ones stay.
    const float c = std::sqrt(0.5f);
    expect_near(half[0].positions[0], {-0.5f, 0, 0});
    expect_near(half[0].positions[2], glm::vec3(-0.5f * c - c, -0.5f * c + c, 0) + glm::vec3(0, 1, 0));
    expect_near(half[0].positions[3], glm::vec3(0.5f * c - c, 0.5f * c + c, 0) + glm::vec3(0, 1, 0));
    expect_near(half[0].normals[2], {0, 0, 1});
    // The clip loops: a whole second on is the same pose.
    EXPECT_EQ(deformed_meshes_at(scene.animation, 1.5)[0].positions, half[0].positions);
}

TEST(MeshDeformation, KeyedWeightsMorphTheirNodesOwnCopy) {
    MorphingTriangle triangle("morphing-triangle.gltf");
    const Scene scene = load(triangle.file);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.animation.deformations.size(), 1u);
    ASSERT_EQ(scene.animation.weight_channels.size(), 1u);
    EXPECT_EQ(scene.meshes.size(), 2u);  // the keyed node's copy, and the one the still node draws
    const MeshDeformation& deformation = scene.animation.deformations[0];
    EXPECT_NE(scene.instances[0].mesh, scene.instances[1].mesh);
    EXPECT_EQ(deformation.mesh, scene.instances[0].mesh);
    expect_near(scene.meshes[deformation.mesh].positions[2], {0, 1, 0});  // weight 0 in the file's pose
    expect_near(deformed_meshes_at(scene.animation, 0.25)[0].positions[2], {0, 1.25f, 0});
    expect_near(deformed_meshes_at(scene.animation, 0.75)[0].positions[2], {0, 1.75f, 0});
}

TEST(MeshDeformation, MalformedWeightChannelsAreLeftOutWithAWarning) {
    MorphingTriangle three_weights("three-weights-per-key.gltf", {0, 1, 0, 1, 0, 1});
    const Scene scene = load(three_weights.file);
    EXPECT_FALSE(scene.animation.plays());
    bool warned = false;
    for (const std::string& warning : scene.warnings)
        warned = warned || warning.find("its output has 6 weights for 2 keys of 1 morph targets") != std::string::npos;
    EXPECT_TRUE(warned);

    GltfBuilder gltf;  // weights keyed on a node whose mesh has no targets
    const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    const int input = float_accessor(gltf, {0, 1}, "SCALAR", 2);
    gltf.document["animations"] = {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}},
                                    {"samplers", {{{"input", input}, {"output", input}}}}}};
    const Scene no_targets = load(gltf.write("weights-without-targets.gltf"));
    warned = false;
    for (const std::string& warning : no_targets.warnings)
        warned = warned || warning.find("whose mesh has no morph targets; left out") != std::string::npos;
    EXPECT_TRUE(warned);
}

// Targets that would take more memory to keep than the file's animations may copy (its buffers' size in floats,
// 16M at least): 4,000 targets sharing one 1,000-vertex accessor would be 36M floats. The mesh is drawn as the file
// poses it, with a warning, and the load stays small.
TEST(MeshDeformation, TargetsTooLargeToAnimateAreDrawnInTheFilesPose) {
    GltfBuilder gltf;
    std::vector<float> xyz;
    for (int v = 0; v < 1000; ++v) xyz.insert(xyz.end(), {float(v % 10), float(v / 10), float(v % 7)});
    const int positions = gltf.positions(xyz);
    json targets = json::array();
    for (int t = 0; t < 4000; ++t) targets.push_back({{"POSITION", positions}});
    gltf.mesh({{{"attributes", {{"POSITION", positions}}}, {"targets", targets}}});
    gltf.node({{"mesh", 0}});
    const int input = float_accessor(gltf, {0}, "SCALAR", 1);
    const int output = float_accessor(gltf, std::vector<float>(4000, 0.0f), "SCALAR", 4000);
    gltf.document["animations"] = {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}},
                                    {"samplers", {{{"input", input}, {"output", output}}}}}};
    const Scene scene = load(gltf.write("too-many-targets.gltf"));
    EXPECT_TRUE(scene.animation.deformations.empty());
    bool warned = false;
    for (const std::string& warning : scene.warnings)
        warned = warned || warning.find("too large to animate") != std::string::npos;
    EXPECT_TRUE(warned);
}

// A posed frame traced through the refitted BVH shows what a BVH built for that pose shows, in every layout.
TEST(MeshDeformation, ARefittedFrameMatchesOneBuiltForThePose) {
    const Scene scene = test::load_test_scene(test::scene("gltf/SimpleSkin/SimpleSkin.gltf").string());
    ASSERT_EQ(scene.animation.deformations.size(), 1u);
    const double seconds = 1.75;
    const Scene posed = test::scene_posed_at(scene, seconds);
    const RenderSettings settings = test::small_settings(64, 48);
    for (BvhLayout layout : {BvhLayout::Stack, BvhLayout::Escape, BvhLayout::Wide}) {
        SCOPED_TRACE(bvh_layout_name(layout));
        BvhBuildOptions options;
        options.layout = layout;
        const FrameResult expected =
            RenderEngine("cpu-ref", build_device_scene(posed, options)).render(scene.camera, settings);
        DeviceScene device = build_device_scene(scene, options);
        ASSERT_EQ(device.deformable_meshes.size(), 1u);
        RenderEngine engine("cpu", device);
        const FrameResult before = engine.render(scene.camera, settings);
        engine.move_to(scene, device, seconds);
        const FrameResult after = engine.render(scene.camera, settings);
        EXPECT_NE(before.image, after.image);
        EXPECT_EQ(after.image, expected.image);
    }
}

// `prism render --frames` plays the skin: the frames differ, a whole loop later is frame 0 again, and `prism info`
// counts the deformed mesh.
TEST(MeshDeformation, ASequenceOfFramesPlaysTheSkin) {
    const std::filesystem::path file = test::scene("gltf/SimpleSkin/SimpleSkin.gltf");
    const std::filesystem::path dir = test::temp_dir("skin-sequence");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    // The clip is 5.5 s long: frame 11 at 2 frames a second is 5.5 s.
    const test::CommandResult r = test::run_prism("render -q --backend cpu --allow-any-path --scene '" + file.string() +
                                                  "' --width 48 --height 32 --depth 1 --frames 0-11 --fps 2 --out '" +
                                                  (dir / "f_%d.png").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto bytes = [&](int frame) { return test::file_bytes(dir / ("f_" + std::to_string(frame) + ".png")); };
    EXPECT_NE(bytes(1), bytes(0));
    EXPECT_NE(bytes(2), bytes(1));
    EXPECT_EQ(bytes(11), bytes(0));
    const test::CommandResult info = test::run_prism("info --allow-any-path --scene '" + file.string() + "' --json -");
    ASSERT_EQ(info.exit_code, 0) << info.output;
    const json animation = json::parse(info.output.substr(info.output.find('{'))).at("scene").at("animation");
    EXPECT_EQ(animation.at("deformed_meshes"), 1);
    EXPECT_EQ(animation.at("moving_instances"), 0);
}

// A scene file placing a skinned model (twice, the second sharing the first's meshes): the mesh is posed in the
// model's space, which the placements carry, so it bends as the model alone does.
TEST(MeshDeformation, APlacedSkinDeformsInTheModelsSpace) {
    BendingStrip strip("placed-strip.gltf");
    std::string text = R"({"objects": [{"file": ")";
    text.append(strip.file.string()).append(R"(", "transform": {"translate": [10, 0, 0]}}, {"file": ")");
    text.append(strip.file.string()).append(R"(", "transform": {"translate": [-10, 0, 0]}}]})");
    const std::filesystem::path scene_file = test::write_file("placed-strips.json", text);
    LoadOptions options;
    options.allow_any_path = true;
    const Scene placed = load_scene(scene_file.string(), options);
    ASSERT_EQ(placed.animation.deformations.size(), 1u);
    EXPECT_EQ(placed.instances.size(), 2u);
    const Scene alone = load(strip.file);
    for (double seconds : {0.25, 0.5}) {
        const std::vector<DeformedVertices> a = deformed_meshes_at(placed.animation, seconds);
        const std::vector<DeformedVertices> b = deformed_meshes_at(alone.animation, seconds);
        for (size_t v = 0; v < b[0].positions.size(); ++v) expect_near(a[0].positions[v], b[0].positions[v]);
    }
}

}  // namespace
}  // namespace prism
