// Punctual lights in the image: a spot's cone and a light's range (glTF KHR_lights_punctual), from the file through
// the loader and the device scene to the shade stage. A matte quad at z = 0 fills most of the frame, lit only by the
// light under test, so every pixel's brightness is that light's falloff.
#include <cmath>
#include <functional>

#include <gtest/gtest.h>

#include "core/loaders/scene_loader.h"
#include "tests/gltf_builder.h"
#include "tests/gltf_render_probe.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::ProbeImage;

constexpr float kPi = 3.14159265358979f;

// A white matte quad 6 x 6 at z = 0 facing the camera, and one glTF light at (0, 0, height) looking down -z.
std::filesystem::path lit_quad(const std::string& name, const json& light, float height) {
    GltfBuilder gltf;
    int positions = gltf.positions({-3, -3, 0, 3, -3, 0, 3, 3, 0, -3, 3, 0});
    int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    int indices = gltf.indices({0, 1, 2, 0, 2, 3});
    gltf.document["materials"] = json::array(
        {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
          {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}});
    gltf.document["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
    gltf.document["extensions"] = {{"KHR_lights_punctual", {{"lights", json::array({light})}}}};
    gltf.node({{"mesh", gltf.mesh(json::array({{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}},
                                                {"indices", indices},
                                                {"material", 0}}}))}});
    gltf.node({{"translation", {0, 0, height}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    return gltf.write(name);
}

// Renders with nothing but the file's light: no ambient light, a black sky.
ProbeImage render(const std::filesystem::path& file) {
    return test::render_gltf(
        file,
        [](Scene& scene) {
            scene.ambient_light = glm::vec3(0.0f);
            scene.environment.color = glm::vec3(0.0f);
        },
        96);
}

// The x in [-1, 1] of the frame where the quad's point at angle `degrees` from the light's axis shows (the light
// `height` above the quad, render_gltf's camera 3 in front of it with a 45-degree field).
float ndc_at_angle(float degrees, float height) {
    return height * std::tan(degrees * kPi / 180.0f) / (3.0f * std::tan(22.5f * kPi / 180.0f));
}

json spot(float inner_degrees, float outer_degrees) {
    return {
        {"type", "spot"},
        {"intensity", 2},
        {"spot", {{"innerConeAngle", inner_degrees * kPi / 180.0f}, {"outerConeAngle", outer_degrees * kPi / 180.0f}}}};
}

uint64_t shadow_rays(const ProbeImage& image) {
    uint64_t total = 0;
    for (uint64_t rays : image.frame.stats.shadow_rays_per_depth) total += rays;
    return total;
}

// Inside the inner angle a spot is the point light it sits at, bit for bit; between the angles it fades; past the
// outer one it gives nothing, and no shadow ray goes there.
TEST(Lights, SpotConeFadesBetweenItsAngles) {
    const float height = 2.0f;
    ProbeImage point = render(lit_quad("point_light.gltf", {{"type", "point"}, {"intensity", 2}}, height));
    ProbeImage cone = render(lit_quad("spot_light.gltf", spot(10, 20), height));
    for (float degrees : {0.0f, 5.0f, 9.0f}) {
        SCOPED_TRACE(degrees);
        float x = ndc_at_angle(degrees, height);
        EXPECT_EQ(cone.at_ndc(x, 0).r, point.at_ndc(x, 0).r);
        EXPECT_GT(cone.at_ndc(x, 0).r, 40);
    }
    // glTF's falloff at 15 degrees: ((cos 15 - cos 20) / (cos 10 - cos 20))^2 = 0.34 of the light, and the image
    // is sRGB-encoded, so between a quarter and three quarters of the point light's byte.
    float x15 = ndc_at_angle(15.0f, height);
    EXPECT_GT(cone.at_ndc(x15, 0).r, point.at_ndc(x15, 0).r / 4);
    EXPECT_LT(cone.at_ndc(x15, 0).r, point.at_ndc(x15, 0).r * 3 / 4);
    // Monotonic from the axis out, the same all round.
    EXPECT_GT(cone.at_ndc(ndc_at_angle(13.0f, height), 0).r, cone.at_ndc(ndc_at_angle(17.0f, height), 0).r);
    EXPECT_NEAR(cone.at_ndc(0, x15).r, cone.at_ndc(-x15, 0).r, 3);
    for (float degrees : {21.0f, 25.0f, 28.0f}) {
        SCOPED_TRACE(degrees);
        EXPECT_EQ(cone.at_ndc(ndc_at_angle(degrees, height), 0).r, 0);
        EXPECT_GT(point.at_ndc(ndc_at_angle(degrees, height), 0).r, 20);
    }
    EXPECT_LT(shadow_rays(cone), shadow_rays(point) / 2);
}

// Equal angles (Blender's spot without blend) give a hard edge, not a division by zero.
TEST(Lights, SpotWithEqualAnglesHasAHardEdge) {
    const float height = 2.0f;
    ProbeImage point = render(lit_quad("point_light_edge.gltf", {{"type", "point"}, {"intensity", 2}}, height));
    ProbeImage cone = render(lit_quad("spot_light_edge.gltf", spot(20, 20), height));
    float inside = ndc_at_angle(18.0f, height), outside = ndc_at_angle(22.0f, height);
    EXPECT_EQ(cone.at_ndc(inside, 0).r, point.at_ndc(inside, 0).r);
    EXPECT_EQ(cone.at_ndc(outside, 0).r, 0);
}

// A range windows the inverse square, 1 - (d / range)^4: dimmer towards the range, nothing beyond it.
TEST(Lights, RangeEndsTheLight) {
    const float height = 1.0f;
    ProbeImage open = render(lit_quad("point_open.gltf", {{"type", "point"}, {"intensity", 0.5}}, height));
    ProbeImage ranged =
        render(lit_quad("point_ranged.gltf", {{"type", "point"}, {"intensity", 0.5}, {"range", 1.2}}, height));
    // Straight below, d = 1: 1 - (1 / 1.2)^4 = 0.52 of the light; at 25 degrees d = 1.10, 0.29 of it.
    EXPECT_LT(ranged.at_ndc(0, 0).r, open.at_ndc(0, 0).r);
    EXPECT_GT(ranged.at_ndc(0, 0).r, open.at_ndc(0, 0).r / 2);
    float x25 = ndc_at_angle(25.0f, height);
    EXPECT_LT(ranged.at_ndc(x25, 0).r, open.at_ndc(x25, 0).r * 3 / 4);
    EXPECT_GT(ranged.at_ndc(x25, 0).r, 0);
    // d > 1.2 beyond 33.6 degrees.
    float x40 = ndc_at_angle(40.0f, height);
    EXPECT_EQ(ranged.at_ndc(x40, 0).r, 0);
    EXPECT_GT(open.at_ndc(x40, 0).r, 20);
    EXPECT_LT(shadow_rays(ranged), shadow_rays(open));
}

// A light the kernels could not use stops the load in one line naming the file and the light.
TEST(Lights, HostileLightValuesAreRefused) {
    auto error_of = [](const std::string& name, const json& light) {
        std::filesystem::path file = lit_quad(name, light, 1.0f);
        LoadOptions options;
        options.allow_any_path = true;
        std::string message = test::error_message([&] { (void)load_scene(file.string(), options); });
        EXPECT_EQ(message.rfind(file.string() + ": light 0", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    };
    EXPECT_NE(error_of("light_huge.gltf", {{"type", "point"}, {"intensity", 1e39}}).find("not a finite"),
              std::string::npos);
    EXPECT_NE(error_of("light_negative.gltf", {{"type", "point"}, {"intensity", -1}}).find("non-negative"),
              std::string::npos);
    EXPECT_NE(error_of("light_cone.gltf", spot(30, 20)).find("cone angles"), std::string::npos);
    EXPECT_NE(error_of("light_wide.gltf", spot(10, 120)).find("cone angles"), std::string::npos);
    EXPECT_NE(error_of("light_range.gltf", {{"type", "point"}, {"range", -2}}).find("range"), std::string::npos);
}

}  // namespace
}  // namespace prism
