// Vertex colours: glTF's COLOR_0 multiplies the material colour; a scene file's material may ask for the seed's
// rule instead ("vertex_colors": "replace"), where the mesh's colours replace the material colour.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/loaders/load_scene_json.h"
#include "core/render/render_engine.h"
#include "tests/gltf_builder.h"
#include "tests/gltf_render_probe.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// The centre pixel of `scene` on cpu-ref, seen from (0, 0, 3) under white ambient light alone, so a surface
// shows its colour as it is.
test::Rgb centre_in_white_ambient_light(Scene scene) {
    scene.lights.clear();
    scene.ambient_light = glm::vec3(1.0f);
    scene.environment.color = glm::vec3(0.0f);
    scene.camera.position = {0.0f, 0.0f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.has_camera = true;
    DeviceScene device = build_device_scene(scene);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.max_depth = 2;
    return test::ProbeImage{RenderEngine("cpu-ref", device).render(scene.camera, settings)}.at_ndc(0.0f, 0.0f);
}

// A red quad (vertex colours) in z = 0 under a material whose own colour is (0.2, 0.2, 1).
test::Rgb render_rule(const std::string& name, const char* rule) {
    std::filesystem::path ply = test::write_file(
        name + ".ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n"
        "-1 -1 0 255 0 0\n1 -1 0 255 0 0\n1 1 0 255 0 0\n-1 1 0 255 0 0\n4 0 1 2 3\n");
    json material = {{"diffuse", {0.2, 0.2, 1.0}}};
    if (rule) material["vertex_colors"] = rule;
    json document = {{"materials", {{"tinted", material}}},
                     {"objects", {{{"file", ply.filename().string()}, {"material", "tinted"}}}}};
    std::filesystem::path file = test::write_file(name + ".json", document.dump());
    return centre_in_white_ambient_light(load_scene_json(file));
}

}  // namespace

TEST(VertexColorRule, MultiplyIsTheDefaultAndReplaceIsTheSeedsRule) {
    test::Rgb multiplied = render_rule("rule_default", nullptr);
    EXPECT_GT(multiplied.r, 100);  // red x (0.2, 0.2, 1) = (0.2, 0, 0)
    EXPECT_LT(multiplied.r, 150);
    EXPECT_LT(multiplied.b, 10);
    test::Rgb explicit_multiply = render_rule("rule_multiply", "multiply");
    EXPECT_EQ(explicit_multiply.r, multiplied.r);
    test::Rgb replaced = render_rule("rule_replace", "replace");
    EXPECT_GT(replaced.r, 240);  // the vertex colour alone
    EXPECT_LT(replaced.b, 10);
}

TEST(VertexColorRule, ReplaceKeepsTheMaterialColourWhereTheMeshHasNoColours) {
    GltfBuilder gltf;
    int positions = gltf.positions({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0});
    int indices = gltf.indices({0, 1, 2, 0, 2, 3});
    gltf.node({{"mesh", gltf.mesh(json::array({{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}}))}});
    std::filesystem::path model = gltf.write("uncoloured_quad.gltf");
    json document = {{"materials", {{"seed", {{"diffuse", {0.0, 1.0, 0.0}}, {"vertex_colors", "replace"}}}}},
                     {"objects", {{{"file", model.filename().string()}, {"material", "seed"}}}}};
    test::Rgb pixel =
        centre_in_white_ambient_light(load_scene_json(test::write_file("uncoloured.json", document.dump())));
    EXPECT_GT(pixel.g, 240);
    EXPECT_LT(pixel.r, 10);
}

TEST(VertexColorRule, UnknownRuleIsAnError) {
    json document = {{"materials", {{"m", {{"vertex_colors", "add"}}}}}};
    std::filesystem::path file = test::write_file("bad_rule.json", document.dump());
    EXPECT_EQ(test::error_message([&] { load_scene_json(file); }),
              file.string() + ": materials.m.vertex_colors: expected multiply or replace");
}

}  // namespace prism
