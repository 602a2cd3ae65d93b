// glTF animations of node transforms (core/scene/node_animation.h, core/loaders/gltf_animation.h): the spec's
// samplers, the loader's channels and nodes, and what a sequence of frames shows.
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

AnimationChannel channel(AnimationPath path, AnimationInterpolation interpolation, std::vector<float> times,
                         std::vector<glm::vec4> values) {
    AnimationChannel c;
    c.path = path;
    c.interpolation = interpolation;
    c.times = std::move(times);
    c.values = std::move(values);
    return c;
}

void expect_near(const glm::vec4& actual, const glm::vec4& expected, float tolerance = 1e-5f) {
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
}

TEST(NodeAnimation, LinearAndStepSamplersHoldTheirEndsAndInterpolateBetween) {
    const AnimationChannel linear = channel(AnimationPath::Translation, AnimationInterpolation::Linear, {1.0f, 3.0f},
                                            {{0, 0, 0, 0}, {4, -2, 8, 0}});
    expect_near(sample_channel(linear, 0.0f), {0, 0, 0, 0});  // before the first key: the first value
    expect_near(sample_channel(linear, 1.5f), {1, -0.5f, 2, 0});
    expect_near(sample_channel(linear, 3.0f), {4, -2, 8, 0});
    expect_near(sample_channel(linear, 9.0f), {4, -2, 8, 0});  // after the last: the last value
    AnimationChannel step = linear;
    step.interpolation = AnimationInterpolation::Step;
    expect_near(sample_channel(step, 2.99f), {0, 0, 0, 0});
    expect_near(sample_channel(step, 3.0f), {4, -2, 8, 0});
}

// Rotations interpolate on the sphere (a quarter turn halfway through a half turn), the short way round, and come
// back normalized.
TEST(NodeAnimation, RotationsInterpolateSphericallyTheShortWay) {
    const float h = std::sqrt(0.5f);
    const AnimationChannel half_turn =
        channel(AnimationPath::Rotation, AnimationInterpolation::Linear, {0.0f, 1.0f}, {{0, 0, 0, 1}, {0, 1, 0, 0}});
    expect_near(sample_channel(half_turn, 0.5f), {0, h, 0, h});
    // -q is the same rotation as q: the path from identity to -(quarter turn) is the quarter turn's, not 3/4 of one.
    const AnimationChannel negated =
        channel(AnimationPath::Rotation, AnimationInterpolation::Linear, {0.0f, 1.0f}, {{0, 0, 0, 1}, {0, -h, 0, -h}});
    const glm::vec4 mid = sample_channel(negated, 0.5f);
    const float angle = 2.0f * std::acos(std::min(1.0f, std::abs(mid.w)));
    EXPECT_NEAR(angle, glm::radians(45.0f), 1e-4f);
    EXPECT_NEAR(glm::length(mid), 1.0f, 1e-6f);
    const AnimationChannel unnormalized =
        channel(AnimationPath::Rotation, AnimationInterpolation::Step, {0.0f}, {{0, 0, 0, 3}});
    expect_near(sample_channel(unnormalized, 0.0f), {0, 0, 0, 1});
}

// CUBICSPLINE (glTF 2.0, Appendix C): three values per key (in-tangent, value, out-tangent); tangents are per
// second, so they are scaled by the key interval. With zero tangents the curve is smoothstep; with tangents, the
// Hermite polynomial at a quarter of a 2-second interval.
TEST(NodeAnimation, CubicSplineIsTheSpecsHermiteCurve) {
    const AnimationChannel flat = channel(AnimationPath::Translation, AnimationInterpolation::CubicSpline, {0.0f, 2.0f},
                                          {{0, 0, 0, 0},
                                           {0, 0, 0, 0},
                                           {0, 0, 0, 0},  // key 0: a, v, b
                                           {0, 0, 0, 0},
                                           {10, 0, 0, 0},
                                           {0, 0, 0, 0}});
    expect_near(sample_channel(flat, 0.5f), {10 * (3 * 0.0625f - 2 * 0.015625f), 0, 0, 0});
    expect_near(sample_channel(flat, 1.0f), {5, 0, 0, 0});
    const AnimationChannel sloped = channel(AnimationPath::Scale, AnimationInterpolation::CubicSpline, {1.0f, 3.0f},
                                            {{9, 9, 9, 0},
                                             {1, 1, 1, 0},
                                             {2, 0, -1, 0},  // key 0's in-tangent unused
                                             {0, 4, 0, 0},
                                             {3, 3, 3, 0},
                                             {9, 9, 9, 0}});  // key 1's out-tangent unused
    const float u = 0.25f, u2 = u * u, u3 = u2 * u, interval = 2.0f;
    const glm::vec4 v0{1, 1, 1, 0}, b0{2, 0, -1, 0}, v1{3, 3, 3, 0}, a1{0, 4, 0, 0};
    const glm::vec4 expected = (2 * u3 - 3 * u2 + 1) * v0 + interval * (u3 - 2 * u2 + u) * b0 +
                               (-2 * u3 + 3 * u2) * v1 + interval * (u3 - u2) * a1;
    expect_near(sample_channel(sloped, 1.5f), expected);
    expect_near(sample_channel(sloped, 0.0f), v0);
    expect_near(sample_channel(sloped, 3.0f), v1);
}

// Finite keys that compose to inf (a scale of 1e30 on two nested nodes) leave the instance where it was.
TEST(NodeAnimation, TransformsThatOverflowKeepTheInstancesPlacement) {
    NodeAnimation animation;
    animation.nodes.resize(2);
    animation.nodes[0].keyed = animation.nodes[1].keyed = true;
    animation.nodes[1].parent = 0;
    for (uint32_t node : {0u, 1u}) {
        AnimationChannel huge = channel(AnimationPath::Scale, AnimationInterpolation::Step, {0.0f}, {{1e30f, 1, 1, 0}});
        huge.node = node;
        animation.channels.push_back(huge);
    }
    animation.instances.push_back({0, 1, glm::mat4(1.0f)});
    animation.duration = 1.0;
    const glm::mat4 placed = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3));
    std::vector<glm::mat4> transforms{placed};
    apply_node_animation(animation, 0.5, transforms);
    EXPECT_EQ(transforms[0], placed);
    animation.channels[1].values[0].x = 2.0f;  // 2e30: finite
    apply_node_animation(animation, 0.5, transforms);
    EXPECT_EQ(transforms[0][0][0], 2e30f);
}

// A triangle on a child node of an animated parent: the parent slides 2 m along x over a second (LINEAR) while the
// child keeps its own offset, its own rotation and scale.
struct SlidingTriangle {
    GltfBuilder gltf;
    std::filesystem::path file;

    explicit SlidingTriangle(const std::string& name, const std::string& interpolation = "LINEAR") {
        const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        const int mesh = gltf.mesh({{{"attributes", {{"POSITION", positions}}}}});
        const int child = gltf.node({{"mesh", mesh}, {"translation", {0, 0, -3}}, {"scale", {2, 2, 2}}});
        gltf.node({{"children", {child}}, {"name", "parent"}, {"translation", {0.5, 0, 0}}});
        const int times = gltf.view(std::vector<float>{0, 1});
        const int input = gltf.accessor({{"bufferView", times},
                                         {"componentType", 5126},
                                         {"count", 2},
                                         {"type", "SCALAR"},
                                         {"min", {0}},
                                         {"max", {1}}});
        const int keys = gltf.view(std::vector<float>{0, 0, 0, 2, 0, 0});
        const int output =
            gltf.accessor({{"bufferView", keys}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
        gltf.document["animations"] = {
            {{"name", "slide"},
             {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}}},
             {"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}}}};
        file = gltf.write(name);
    }
};

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_gltf(path, scene);
    return scene;
}

glm::vec3 translation_of(const glm::mat4& m) { return glm::vec3(m[3]); }

TEST(NodeAnimation, AParentsChannelMovesTheMeshBelowIt) {
    SlidingTriangle sliding("sliding-triangle.gltf");
    const Scene scene = load(sliding.file);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_TRUE(scene.animation.plays());
    EXPECT_EQ(scene.animation.name, "slide");
    EXPECT_DOUBLE_EQ(scene.animation.duration, 1.0);
    ASSERT_EQ(scene.instances.size(), 1u);
    // A still render shows the nodes as the file places them.
    EXPECT_EQ(translation_of(scene.instances[0].transform), glm::vec3(0.5f, 0, -3));
    const std::vector<glm::mat4> half = instance_transforms_at(scene, 0.5);
    EXPECT_EQ(translation_of(half[0]), glm::vec3(1, 0, -3));
    EXPECT_EQ(glm::vec3(half[0][0]), glm::vec3(2, 0, 0));  // the child's scale stays
    EXPECT_EQ(translation_of(instance_transforms_at(scene, 0.0)[0]), glm::vec3(0, 0, -3));
    EXPECT_EQ(instance_transforms_at(scene, 2.5)[0], half[0]);  // the sequence loops over the duration
    EXPECT_TRUE(scene_moves(scene));
}

TEST(NodeAnimation, StepChannelsJumpAtTheirKeys) {
    SlidingTriangle sliding("stepping-triangle.gltf", "STEP");
    const Scene scene = load(sliding.file);
    EXPECT_EQ(translation_of(instance_transforms_at(scene, 0.75)[0]), glm::vec3(0, 0, -3));
    EXPECT_EQ(translation_of(instance_transforms_at(scene, 0.999)[0]), glm::vec3(0, 0, -3));
    EXPECT_EQ(translation_of(instance_transforms_at(scene, 1.0 + 1e-3)[0]), glm::vec3(0, 0, -3));  // looped
}

// What cannot play is said in one warning and the file loads as before: a channel on a node with nothing below it,
// malformed channels (named, with their cause: weights of a mesh without morph targets, an output of the wrong
// type), and more than one animation.
TEST(NodeAnimation, ChannelsThatCannotPlayAreLeftOutWithAWarning) {
    SlidingTriangle sliding("partly-playable.gltf");
    json& animations = sliding.gltf.document["animations"];
    const int empty = sliding.gltf.node({{"name", "empty"}});
    json& channels = animations[0]["channels"];
    channels.push_back({{"sampler", 0}, {"target", {{"node", empty}, {"path", "translation"}}}});
    channels.push_back({{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}});
    channels.push_back({{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}});  // VEC3 output: malformed
    animations[0]["samplers"].push_back(animations[0]["samplers"][0]);
    animations.push_back(animations[0]);
    animations[1]["name"] = "second";
    const Scene scene = load(sliding.gltf.write("partly-playable.gltf"));
    ASSERT_TRUE(scene.animation.plays());
    EXPECT_EQ(scene.animation.channels.size(), 1u);
    ASSERT_EQ(scene.warnings.size(), 4u) << ::testing::PrintToString(scene.warnings);
    EXPECT_NE(scene.warnings[0].find("channel 2: it keys the weights of node 0, whose mesh has no morph targets; left "
                                     "out"),
              std::string::npos)
        << scene.warnings[0];
    EXPECT_NE(scene.warnings[1].find("channel 3: its output has 3 components; 4 expected; left out"), std::string::npos)
        << scene.warnings[1];
    EXPECT_NE(scene.warnings[2].find("has 2 animations; sequences and the viewer play the first, 'slide' (--animation"),
              std::string::npos)
        << scene.warnings[2];
    EXPECT_NE(scene.warnings[3].find("animation 'slide': 3 of its 4 channels are not played"), std::string::npos)
        << scene.warnings[3];
}

// A file of many malformed channels gets eight lines naming them and one counting the rest; a name from the file
// is quoted short and without control characters.
TEST(NodeAnimation, ManyMalformedChannelsAreCountedNotListed) {
    SlidingTriangle sliding("many-malformed.gltf");
    json& animation = sliding.gltf.document["animations"][0];
    animation["name"] = "\x1b[2J" + std::string(500, 'n');
    for (int i = 0; i < 100; ++i)
        animation["channels"].push_back({{"sampler", 7}, {"target", {{"node", 1}, {"path", "scale"}}}});
    const Scene scene = load(sliding.gltf.write("many-malformed.gltf"));
    EXPECT_TRUE(scene.animation.plays());
    ASSERT_EQ(scene.warnings.size(), 10u);  // eight named, the count, the channels not played
    for (const std::string& warning : scene.warnings) {
        EXPECT_EQ(warning.find('\x1b'), std::string::npos) << warning;
        EXPECT_LT(warning.size(), 400u) << warning;
    }
    EXPECT_NE(scene.warnings[7].find("channel 8: its sampler does not exist; left out"), std::string::npos)
        << scene.warnings[7];
    EXPECT_NE(scene.warnings[8].find("92 more malformed animation channels left out"), std::string::npos)
        << scene.warnings[8];
    EXPECT_NE(scene.warnings[9].find("100 of its 101 channels are not played"), std::string::npos) << scene.warnings[9];
}

// Channels may share one large accessor (here zero-filled ones, which claim 4 MiB of buffer and hold nothing), so a
// small file could make every channel copy it: the copies stop at a budget (the buffers' bytes in floats, 16M at
// least), and the channels past it are left out with a warning.
TEST(NodeAnimation, KeysSharedByManyChannelsStayWithinABudget) {
    SlidingTriangle sliding("key-budget.gltf");
    GltfBuilder& gltf = sliding.gltf;
    gltf.view(std::vector<float>(size_t(1) << 20));  // 4 MiB that zero-filled accessors may claim
    const size_t keys = (size_t(4) << 20) / 12;      // VEC3 elements of that
    const int times = gltf.accessor({{"componentType", 5126}, {"count", keys}, {"type", "SCALAR"}});
    const int values = gltf.accessor({{"componentType", 5126}, {"count", keys}, {"type", "VEC3"}});
    json& animation = gltf.document["animations"][0];
    animation["samplers"].push_back({{"input", times}, {"output", values}, {"interpolation", "STEP"}});
    for (int i = 0; i < 30; ++i)
        animation["channels"].push_back({{"sampler", 1}, {"target", {{"node", 1}, {"path", "scale"}}}});
    const Scene scene = load(gltf.write("key-budget.gltf"));
    size_t floats = 0;
    for (const AnimationChannel& c : scene.animation.channels) floats += c.times.size() + 3 * c.values.size();
    EXPECT_LE(floats, size_t(16) << 20);
    EXPECT_GT(scene.animation.channels.size(), 2u);
    EXPECT_LT(scene.animation.channels.size(), 31u);
    ASSERT_FALSE(scene.warnings.empty());
    EXPECT_NE(scene.warnings[0].find("would pass what the file's channels may copy in all"), std::string::npos)
        << scene.warnings[0];
}

TEST(NodeAnimation, AnAnimationThatMovesNoMeshIsNotPlayed) {
    GltfBuilder gltf;
    const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    const int camera_node = gltf.node({{"name", "camera rig"}});
    const int times = gltf.view(std::vector<float>{0, 1});
    const int input = gltf.accessor({{"bufferView", times}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int keys = gltf.view(std::vector<float>{0, 0, 0, 1, 0, 0});
    const int output = gltf.accessor({{"bufferView", keys}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    gltf.document["animations"] = {
        {{"channels", {{{"sampler", 0}, {"target", {{"node", camera_node}, {"path", "translation"}}}}}},
         {"samplers", {{{"input", input}, {"output", output}}}}}};
    const Scene scene = load(gltf.write("moves-nothing.gltf"));
    EXPECT_FALSE(scene.animation.plays());
    EXPECT_FALSE(scene_moves(scene));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("animation 'animation 0' is not played"), std::string::npos) << scene.warnings[0];
}

// Hostile keys are left out, not played: a NaN key value, times that go back, a time accessor that is not SCALAR.
TEST(NodeAnimation, HostileKeysAreRefusedPerChannel) {
    struct Case {
        std::vector<float> times, values;
        const char* cause;
    };
    const Case cases[] = {{{0, 1}, {0, 0, 0, NAN, 0, 0}, "a key value is not finite"},
                          {{1, 0}, {0, 0, 0, 1, 0, 0}, "its key times decrease"},
                          {{0, INFINITY}, {0, 0, 0, 1, 0, 0}, "a key time is not finite"}};
    for (const Case& c : cases) {
        SlidingTriangle sliding("hostile-keys.gltf");
        GltfBuilder& gltf = sliding.gltf;
        const int times = gltf.view(c.times);
        const int keys = gltf.view(c.values);
        gltf.document["accessors"][gltf.document["animations"][0]["samplers"][0]["input"].get<int>()]["bufferView"] =
            times;
        gltf.document["accessors"][gltf.document["animations"][0]["samplers"][0]["output"].get<int>()]["bufferView"] =
            keys;
        const Scene scene = load(gltf.write("hostile-keys.gltf"));
        EXPECT_FALSE(scene.animation.plays()) << c.cause;
        ASSERT_FALSE(scene.warnings.empty()) << c.cause;
        EXPECT_NE(scene.warnings[0].find(std::string("channel 0: ") + c.cause + "; left out"), std::string::npos)
            << scene.warnings[0];
    }
}

// A camera below an animated node moves over a sequence (a still keeps the file's pose); other cameras do not.
TEST(NodeAnimation, TheScenesCameraFollowsItsNode) {
    SlidingTriangle sliding("camera-rig.gltf");
    GltfBuilder& gltf = sliding.gltf;
    gltf.document["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    const int camera = gltf.node({{"camera", 0}, {"translation", {0, 0, 4}}});
    gltf.document["nodes"][1]["children"].push_back(camera);  // beside the triangle, below the sliding parent
    const Scene scene = load(gltf.write("camera-rig.gltf"));
    ASSERT_TRUE(scene.has_camera);
    EXPECT_EQ(scene.camera.position, glm::vec3(0.5f, 0, 4));
    EXPECT_EQ(scene.animation.camera_node, 2);  // the parent, the triangle's node, the camera's node
    EXPECT_EQ(camera_at(scene, 0.5).position, glm::vec3(1, 0, 4));
    EXPECT_EQ(camera_at(scene, 0.5).target, glm::vec3(1, 0, 3));
    EXPECT_NEAR(camera_at(scene, 0.5).vertical_fov_degrees, glm::degrees(0.8f), 1e-4f);
    // Only the camera moves: still an animation that plays.
    gltf.document["nodes"][1]["children"] = {camera};
    const Scene camera_only = load(gltf.write("camera-only.gltf"));
    EXPECT_TRUE(camera_only.animation.plays());
    EXPECT_TRUE(camera_only.animation.instances.empty());
    EXPECT_EQ(camera_at(camera_only, 0.75).position, glm::vec3(1.5f, 0, 4));
}

// A camera whose node gives no view (scale 0) or whose yfov is no field of view is left out with a warning: the
// scene is framed as one without a camera, with a finite camera.
TEST(NodeAnimation, ACameraThatGivesNoViewIsLeftToTheFraming) {
    for (const auto& [scale, yfov] : {std::pair{0.0, 0.8}, std::pair{1.0, 0.0}, std::pair{1.0, 4.0}}) {
        GltfBuilder gltf;
        const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
        gltf.document["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", yfov}, {"znear", 0.1}}}}};
        gltf.node({{"camera", 0}, {"translation", {0, 0, 4}}, {"scale", {scale, scale, scale}}});
        LoadOptions options;
        options.allow_any_path = true;
        const Scene scene = load_scene(gltf.write("no-view.gltf").string(), options);
        ASSERT_FALSE(scene.warnings.empty());
        EXPECT_NE(scene.warnings[0].find("camera 0 gives no view"), std::string::npos) << scene.warnings[0];
        for (int i = 0; i < 3; ++i) {
            EXPECT_TRUE(std::isfinite(scene.camera.position[i]));
            EXPECT_TRUE(std::isfinite(scene.camera.target[i]));
        }
        EXPECT_NE(scene.camera.position, scene.camera.target);
    }
}

// A scene file places an animated model twice: each copy plays below its own placement.
TEST(NodeAnimation, ASceneFilePlaysEachPlacedCopy) {
    SlidingTriangle sliding("placed-twice.gltf");
    const std::filesystem::path scene_file =
        test::write_file("placed-twice.json", R"({"objects": [{"file": "placed-twice.gltf"},
            {"file": "placed-twice.gltf", "transform": {"translate": [0, 10, 0], "scale": 2}}]})");
    ASSERT_EQ(scene_file.parent_path(), sliding.file.parent_path());
    Scene scene;
    {
        LoadOptions options;
        options.allow_any_path = true;
        scene = load_scene(scene_file.string(), options);
    }
    ASSERT_EQ(scene.instances.size(), 2u);
    ASSERT_TRUE(scene.animation.plays());
    EXPECT_EQ(scene.animation.instances.size(), 2u);
    const std::vector<glm::mat4> half = instance_transforms_at(scene, 0.5);
    EXPECT_EQ(translation_of(half[0]), glm::vec3(1, 0, -3));
    EXPECT_EQ(translation_of(half[1]), glm::vec3(2, 10, -6));
    EXPECT_EQ(glm::vec3(half[1][0]), glm::vec3(4, 0, 0));  // the child's scale 2 times the placement's 2
    // At rest, the scene file's placements as loaded.
    EXPECT_EQ(translation_of(scene.instances[1].transform), glm::vec3(1, 10, -6));
}

// docs/examples/animated-boxes.gltf has two animations: "spin" (a red box's rotation, 4 s) and "bounce and pulse"
// (a green box's CUBICSPLINE translation over 2 s, a blue box's STEP scale over 1.5 s). --animation (a bare glTF) and
// an object's "animation" (a scene file) pick the first, one by index or name, or all; each clip loops on its own.
TEST(NodeAnimation, AnimationIsPickedByIndexNameOrAll) {
    const std::filesystem::path boxes =
        std::filesystem::path(PRISM_SOURCE_DIR) / "docs" / "examples" / "animated-boxes.gltf";
    auto load_picked = [&](const std::string& animation) {
        LoadOptions options;
        options.allow_any_path = true;
        options.animation = animation;
        return load_scene(boxes.string(), options);
    };
    const Scene first = load_picked("");
    EXPECT_EQ(first.animation.name, "spin");
    EXPECT_DOUBLE_EQ(first.animation.duration, 4.0);
    ASSERT_EQ(first.warnings.size(), 1u);
    EXPECT_NE(first.warnings[0].find("has 2 animations; sequences and the viewer play the first, 'spin' (--animation"),
              std::string::npos)
        << first.warnings[0];
    for (const char* second : {"1", "bounce and pulse"}) {
        const Scene picked = load_picked(second);
        EXPECT_EQ(picked.animation.name, "bounce and pulse") << second;
        EXPECT_EQ(picked.animation.channels.size(), 2u) << second;
        EXPECT_TRUE(picked.warnings.empty()) << second;
    }
    const Scene all = load_picked("all");
    EXPECT_EQ(all.animation.name, "all 2 animations");
    EXPECT_EQ(all.animation.channels.size(), 3u);
    EXPECT_DOUBLE_EQ(all.animation.duration, 4.0);
    // Each clip loops on its own: at 2.5 s the bounce (2 s) is half a second into its second round, as at 0.5 s.
    const std::vector<glm::mat4> early = instance_transforms_at(all, 0.5), late = instance_transforms_at(all, 2.5);
    EXPECT_EQ(translation_of(late[1]), translation_of(early[1]));
    EXPECT_NE(late[0], early[0]);  // the spin (4 s) went on
    // What the file does not have is a one-line error that lists what it has.
    EXPECT_EQ(test::error_message([&] { (void)load_picked("run"); }),
              boxes.string() + ": no animation 'run' (it has 2: 0 'spin', 1 'bounce and pulse'; or all)");
    EXPECT_EQ(test::error_message([&] { (void)load_picked("2"); }).find("no animation '2'") != std::string::npos, true);
    LoadOptions on_ply;
    on_ply.animation = "0";
    EXPECT_EQ(test::error_message([&] { (void)load_scene("builtin:sphere", on_ply); }),
              "builtin:sphere: --animation picks a glTF file's animation; this scene has none");
}

TEST(NodeAnimation, ASceneFileObjectPicksItsModelsAnimation) {
    const std::filesystem::path examples = std::filesystem::path(PRISM_SOURCE_DIR) / "docs" / "examples";
    LoadOptions options;
    options.allow_any_path = true;
    const Scene scene = load_scene((examples / "animated-boxes.json").string(), options);
    EXPECT_EQ(scene.animation.name, "all 2 animations");
    EXPECT_EQ(scene.animation.instances.size(), 3u);
    std::string text = R"({"objects": [{"file": ")";
    text.append(test::scene("stanford/bunny_res2.ply").string()).append(R"(", "animation": 0}]})");
    const std::filesystem::path bad = test::write_file("animation-on-a-ply.json", text);
    EXPECT_NE(test::error_message([&] {
                  (void)load_scene(bad.string(), options);
              }).find("objects[0].animation: only glTF models have animations"),
              std::string::npos);
}

// A light below a keyed node moves with it (KHR_lights_punctual on an animated node): a spot light sliding over a
// floor that stays, shining down its node's -z; RenderEngine::move_to traces the frame a scene built with the light
// in that place traces.
TEST(NodeAnimation, ALightBelowAKeyedNodeMovesWithIt) {
    GltfBuilder gltf;
    const int positions = gltf.positions({-4, 0, -4, 4, 0, -4, -4, 0, 4, 4, 0, 4});
    gltf.node({{"name", "floor"},
               {"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}},
                                    {"indices", gltf.indices({0, 2, 1, 1, 2, 3})}}})}});
    gltf.document["extensionsUsed"] = {"KHR_lights_punctual"};
    gltf.document["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"intensity", 40}, {"spot", {{"outerConeAngle", 0.4}}}}};
    const float h = std::sqrt(0.5f);
    gltf.node({{"name", "lamp"},
               {"translation", {-2, 3, 0}},
               {"rotation", {-h, 0, 0, h}},  // -z turned to point down
               {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const int input = gltf.accessor({{"bufferView", gltf.view(std::vector<float>{0, 1})},
                                     {"componentType", 5126},
                                     {"count", 2},
                                     {"type", "SCALAR"}});
    const int output = gltf.accessor({{"bufferView", gltf.view(std::vector<float>{-2, 3, 0, 2, 3, 0})},
                                      {"componentType", 5126},
                                      {"count", 2},
                                      {"type", "VEC3"}});
    gltf.document["animations"] = {
        {{"name", "sweep"},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}}},
         {"samplers", {{{"input", input}, {"output", output}}}}}};
    const Scene scene = load(gltf.write("sweeping-lamp.gltf"));
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_TRUE(scene.animation.plays());
    ASSERT_EQ(scene.animation.lights.size(), 1u);
    EXPECT_TRUE(scene_moves(scene));
    const std::vector<Light> half = lights_at(scene, 0.5);
    EXPECT_NEAR(glm::distance(half[0].position, glm::vec3(0, 3, 0)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(half[0].direction, glm::vec3(0, -1, 0)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(scene.lights[0].position, glm::vec3(-2, 3, 0)), 0.0f, 1e-5f);  // the file's place

    Camera camera;
    camera.position = {0, 6, 6};
    camera.target = {0, 0, 0};
    const RenderSettings settings = test::small_settings(64, 48, 2);
    DeviceScene device = build_device_scene(scene);
    RenderEngine engine("cpu", device);
    const FrameResult still = engine.render(camera, settings);
    engine.move_to(scene, device, 0.75);
    const FrameResult moved = engine.render(camera, settings);
    const FrameResult expected =
        RenderEngine("cpu", build_device_scene(test::scene_posed_at(scene, 0.75))).render(camera, settings);
    EXPECT_EQ(moved.image, expected.image);
    EXPECT_NE(moved.image, still.image);
}

// `prism render --frames`: frame N shows the animation at N / fps seconds, and a frame a whole loop later is the
// same image.
TEST(NodeAnimation, ASequenceOfFramesPlaysTheAnimation) {
    SlidingTriangle sliding("sequence-triangle.gltf");
    const std::filesystem::path dir = test::temp_dir("animation-sequence");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const test::CommandResult r = test::run_prism(
        "render -q --backend cpu --allow-any-path --scene '" + sliding.file.string() +
        "' --width 48 --height 32 --depth 1 --frames 0-4 --fps 4 --out '" + (dir / "f_%d.png").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    auto bytes = [&](int frame) { return test::file_bytes(dir / ("f_" + std::to_string(frame) + ".png")); };
    EXPECT_NE(bytes(1), bytes(0));
    EXPECT_NE(bytes(2), bytes(1));
    EXPECT_EQ(bytes(4), bytes(0));
    // `prism info` says what will play.
    const test::CommandResult info =
        test::run_prism("info --allow-any-path --scene '" + sliding.file.string() + "' --json -");
    ASSERT_EQ(info.exit_code, 0) << info.output;
    const json animation = json::parse(info.output.substr(info.output.find('{'))).at("scene").at("animation");
    EXPECT_EQ(animation.at("name"), "slide");
    EXPECT_EQ(animation.at("seconds"), 1.0);
    EXPECT_EQ(animation.at("channels"), 1);
    EXPECT_EQ(animation.at("moving_instances"), 1);
}

}  // namespace
}  // namespace prism
