// glTF material channels beyond the base colour, checked on rendered pixels (cpu-ref; the backends run the same
// kernels/ code, and the agreement tests compare them): emissive texture and strength, metallic-roughness
// texture, occlusion on the ambient term.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include <glm/glm.hpp>

#include "core/loaders/gltf_spec_gloss.h"
#include "tests/gltf_builder.h"
#include "tests/gltf_render_probe.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

constexpr uint32_t kRed = 0xff0000ffu, kGreen = 0xff00ff00u, kBlue = 0xffff0000u, kWhite = 0xffffffffu,
                   kBlack = 0xff000000u;

// A unit quad in z = 0 facing +z with uv (0, 0) at its top-left corner, so texel (0, 0) of a 2x2 texture covers
// the top-left quarter of the quad on screen.
// With `tangents`, a TANGENT attribute along +x (+u) is given; else the loader generates it.
int textured_quad(GltfBuilder& gltf, bool tangents = false) {
    int positions = gltf.positions({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0});
    int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
    int uvs = gltf.accessor({{"bufferView", gltf.view(uv)}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
    int indices = gltf.indices({0, 1, 2, 0, 2, 3});
    json attributes = {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uvs}};
    if (tangents) {
        std::vector<float> xyzw = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
        attributes["TANGENT"] =
            gltf.accessor({{"bufferView", gltf.view(xyzw)}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
    }
    return gltf.mesh(json::array({{{"attributes", attributes}, {"indices", indices}, {"material", 0}}}));
}

// One texture per image name, sampled nearest-texel-centre by the probes.
void add_textures(GltfBuilder& gltf, const std::vector<std::string>& images) {
    for (size_t i = 0; i < images.size(); ++i) {
        gltf.document["images"].push_back({{"uri", images[i]}});
        gltf.document["textures"].push_back({{"source", i}});
    }
}

// The pixel showing world point (x, y) of the z = 0 plane from render_gltf's camera (45 degrees, distance 3).
test::Rgb at_world(const test::ProbeImage& image, float x, float y) {
    const float ndc_per_unit = 1.0f / (3.0f * std::tan(glm::radians(22.5f)));
    return image.at_ndc(x * ndc_per_unit, y * ndc_per_unit);
}

bool is_red(test::Rgb c) { return c.r > 200 && c.g < 60 && c.b < 60; }
bool is_green(test::Rgb c) { return c.g > 200 && c.r < 60 && c.b < 60; }
bool is_blue(test::Rgb c) { return c.b > 200 && c.r < 60 && c.g < 60; }

// A document whose material 0 has the alpha mode and base colour factor of `mode_and_factor` ({"mode", "factor"}),
// textured (when `textured`) by a 2x2 red image whose left column has alpha 0; no nodes yet.
GltfBuilder alpha_quad(json mode_and_factor, bool textured) {
    constexpr uint32_t kClearRed = 0x000000ffu;  // red, alpha 0
    std::string image = test::write_test_png("alpha_cutout.png", 2, 2, {kClearRed, kRed, kClearRed, kRed});
    GltfBuilder gltf;
    add_textures(gltf, {image});
    json pbr = {{"baseColorFactor", mode_and_factor["factor"]}, {"metallicFactor", 0}};
    if (textured) pbr["baseColorTexture"] = {{"index", 0}};
    gltf.document["materials"] = json::array({{{"pbrMetallicRoughness", pbr}, {"alphaMode", mode_and_factor["mode"]}}});
    return gltf;
}

// A node of textured_quad turned about x by `tilt_degrees` (-75: seen at a grazing angle from render_gltf's camera).
void add_tilted_quad(GltfBuilder& gltf, double tilt_degrees) {
    double half = tilt_degrees * 3.14159265358979 / 360.0;
    gltf.node({{"mesh", textured_quad(gltf)}, {"rotation", {std::sin(half), 0, 0, std::cos(half)}}});
}

// Lit only by a white sky: what a surface shows is what it mirrors.
void white_sky(Scene& scene) {
    scene.lights.clear();
    scene.ambient_light = glm::vec3(0.0f);
    scene.environment.kind = EnvironmentKind::Constant;
    scene.environment.color = glm::vec3(1.0f);
}

// No lights, a uniform green sky, and `ambient` of ambient light.
std::function<void(Scene&)> green_sky_lit_by(float ambient) {
    return [ambient](Scene& scene) {
        scene.lights.clear();
        scene.ambient_light = glm::vec3(ambient);
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = glm::vec3(0.0f, 1.0f, 0.0f);
    };
}

void no_light(Scene& scene) {
    scene.lights.clear();
    scene.ambient_light = glm::vec3(0.0f);
    scene.environment.color = glm::vec3(0.0f);
}

}  // namespace

TEST(GltfMaterialMaps, EmissiveTextureShowsItsColours) {
    std::string image = test::write_test_png("emissive_rgbw.png", 2, 2, {kRed, kGreen, kBlue, kWhite});
    auto build = [&](const std::string& name, json emissive_factor, json extensions) {
        GltfBuilder gltf;
        add_textures(gltf, {image});
        json material = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                         {"emissiveFactor", emissive_factor},
                         {"emissiveTexture", {{"index", 0}}}};
        if (!extensions.is_null()) material["extensions"] = extensions;
        gltf.document["materials"] = json::array({material});
        gltf.node({{"mesh", textured_quad(gltf)}});
        return gltf.write(name);
    };
    test::ProbeImage plain = test::render_gltf(build("emissive.gltf", {1, 1, 1}, nullptr), no_light);
    // Texel centres: world (+-0.5, +-0.5).
    test::Rgb top_left = at_world(plain, -0.5f, 0.5f), top_right = at_world(plain, 0.5f, 0.5f);
    test::Rgb bottom_left = at_world(plain, -0.5f, -0.5f), bottom_right = at_world(plain, 0.5f, -0.5f);
    EXPECT_GT(top_left.r, 200);
    EXPECT_LT(top_left.g, 60);
    EXPECT_GT(top_right.g, 200);
    EXPECT_LT(top_right.r, 60);
    EXPECT_GT(bottom_left.b, 200);
    EXPECT_LT(bottom_left.g, 60);
    EXPECT_GT(bottom_right.r, 200);
    EXPECT_GT(bottom_right.b, 200);

    // KHR_materials_emissive_strength scales the factor: 0.25 x 4 is the same light.
    test::ProbeImage strong =
        test::render_gltf(build("emissive_strength.gltf", {0.25, 0.25, 0.25},
                                {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}),
                          no_light);
    EXPECT_GE(test::psnr_rgba8(plain.frame.image, strong.frame.image), 50.0);
    test::ProbeImage dim = test::render_gltf(build("emissive_dim.gltf", {0.25, 0.25, 0.25}, nullptr), no_light);
    EXPECT_LT(at_world(dim, -0.5f, 0.5f).r, top_left.r - 50);
}

// KHR_materials_transmission with metallicFactor 1 (glTF's default) and the real values in the texture, over an
// emissive red wall under a green sky: the dielectric half transmits and shows the red wall behind it, the metal half
// mirrors the green sky in front (GlassHurricaneCandleHolder's glass and chrome foot share one such material).
TEST(GltfMaterialMaps, TransmissionTakesMetallicFromTheTexture) {
    std::string image = test::write_test_png("metal_rough_glass.png", 2, 2, {kBlack, kBlue, kBlack, kBlue});
    GltfBuilder gltf;
    add_textures(gltf, {image});
    gltf.document["materials"] = json::array(
        {{{"pbrMetallicRoughness",
           {{"baseColorFactor", {1, 1, 1, 1}}, {"roughnessFactor", 0}, {"metallicRoughnessTexture", {{"index", 0}}}}},
          {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}},
         {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
          {"emissiveFactor", {1, 0, 0}}}});
    gltf.node({{"mesh", textured_quad(gltf)}});
    const int wall = textured_quad(gltf);
    gltf.document["meshes"][wall]["primitives"][0]["material"] = 1;
    gltf.node({{"mesh", wall}, {"translation", {0, 0, -1}}, {"scale", {4, 4, 1}}});
    test::ProbeImage image_out = test::render_gltf(gltf.write("metal_rough_glass.gltf"), green_sky_lit_by(0.0f));
    test::Rgb glass = at_world(image_out, -0.5f, 0.0f), metal = at_world(image_out, 0.5f, 0.0f);
    EXPECT_GT(glass.r, 150) << "the red wall through the glass";
    EXPECT_GT(metal.g, 150) << "the green sky in the metal";
    EXPECT_LT(metal.r, 60);
}

// metallicFactor 1 with the real values in the texture (B = metallic, G = roughness): the metal half mirrors the
// green sky, the dielectric half stays a grey diffuse surface.
TEST(GltfMaterialMaps, MetallicRoughnessTextureDecidesWhatMirrors) {
    // Left column dielectric (B = 0), right column smooth metal (B = 255, G = 0).
    std::string image = test::write_test_png("metal_rough.png", 2, 2, {kBlack, kBlue, kBlack, kBlue});
    GltfBuilder gltf;
    add_textures(gltf, {image});
    gltf.document["materials"] = json::array({{{"pbrMetallicRoughness",
                                                {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                                                 {"metallicFactor", 1},
                                                 {"roughnessFactor", 1},
                                                 {"metallicRoughnessTexture", {{"index", 0}}}}}}});
    gltf.node({{"mesh", textured_quad(gltf)}});
    test::ProbeImage image_out = test::render_gltf(gltf.write("metal_rough.gltf"), green_sky_lit_by(0.5f));
    test::Rgb dielectric = at_world(image_out, -0.5f, 0.0f), metal = at_world(image_out, 0.5f, 0.0f);
    EXPECT_LT(dielectric.g - dielectric.r, 25);  // grey: the ambient light, and Fresnel's few % of the sky
    EXPECT_GT(dielectric.r, 60);
    EXPECT_LT(metal.r, 20);  // a mirror of the green sky, tinted by the grey base colour
    EXPECT_GT(metal.g, 150);
}

// KHR_materials_pbrSpecularGlossiness, converted to metallic-roughness: a plastic (specular 0.04) keeps its diffuse
// colour as base colour and no metal, a material whose specular is its colour and whose diffuse is black is a metal.
TEST(GltfMaterialMaps, SpecularGlossinessFactorsConvertToMetallicRoughness) {
    const gltf::MetallicRoughness plastic =
        gltf::metallic_roughness_of({glm::vec4(0.5f, 0.2f, 0.1f, 0.8f), glm::vec3(0.04f), 0.7f});
    EXPECT_EQ(plastic.metallic, 0.0f);
    EXPECT_NEAR(plastic.base.x, 0.5f, 1e-5f);
    EXPECT_NEAR(plastic.base.y, 0.2f, 1e-5f);
    EXPECT_NEAR(plastic.base.z, 0.1f, 1e-5f);
    EXPECT_EQ(plastic.base.w, 0.8f);
    EXPECT_NEAR(plastic.roughness, 0.3f, 1e-6f);
    const gltf::MetallicRoughness gold =
        gltf::metallic_roughness_of({glm::vec4(0.0f, 0.0f, 0.0f, 1.0f), glm::vec3(1.0f, 0.78f, 0.34f), 1.0f});
    EXPECT_NEAR(gold.metallic, 1.0f, 1e-3f);
    EXPECT_NEAR(gold.base.x, 1.0f, 1e-3f);
    EXPECT_NEAR(gold.base.y, 0.78f, 1e-3f);
    EXPECT_NEAR(gold.base.z, 0.34f, 1e-3f);
    EXPECT_EQ(gold.roughness, 0.0f);
}

// The same through textures, as exporters wrote it: left column grey plastic, right column a white mirror-metal
// (specular white, diffuse black). Under a green sky the plastic stays grey and the metal mirrors the sky; before
// the extension was read, the quad was the default white.
TEST(GltfMaterialMaps, SpecularGlossinessTexturesDecideWhatMirrors) {
    constexpr uint32_t kGrey = 0xffbcbcbcu, kPlasticSpecular = 0xff383838u;  // sRGB 0.5 and 0.04 linear
    std::string diffuse = test::write_test_png("sg_diffuse.png", 2, 2, {kGrey, kBlack, kGrey, kBlack});
    std::string spec_gloss =
        test::write_test_png("sg_specgloss.png", 2, 2, {kPlasticSpecular, kWhite, kPlasticSpecular, kWhite});
    GltfBuilder gltf;
    add_textures(gltf, {diffuse, spec_gloss});
    json extension = {{"diffuseTexture", {{"index", 0}}}, {"specularGlossinessTexture", {{"index", 1}}}};
    gltf.document["materials"] = json::array({{{"extensions", {{"KHR_materials_pbrSpecularGlossiness", extension}}}}});
    gltf.document["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    gltf.document["extensionsRequired"] = {"KHR_materials_pbrSpecularGlossiness"};
    gltf.node({{"mesh", textured_quad(gltf)}});
    test::ProbeImage image_out = test::render_gltf(gltf.write("spec_gloss.gltf"), green_sky_lit_by(0.5f));
    test::Rgb plastic = at_world(image_out, -0.5f, 0.0f), metal = at_world(image_out, 0.5f, 0.0f);
    EXPECT_LT(plastic.g - plastic.r, 25);  // grey: the ambient light, and Fresnel's few % of the sky
    EXPECT_GT(plastic.r, 60);
    EXPECT_LT(metal.r, 40);  // a mirror of the green sky (and the ambient term on its white base colour)
    EXPECT_GT(metal.g, 150);
}

// KHR_materials_unlit: the base colour texture shows as it is with no light at all, and nothing is mirrored (the
// material's metallic factor of 1 would otherwise make it a mirror of the black sky).
TEST(GltfMaterialMaps, UnlitMaterialShowsItsBaseColourWithoutLight) {
    std::string image = test::write_test_png("unlit.png", 2, 2, {kRed, kGreen, kRed, kGreen});
    GltfBuilder gltf;
    add_textures(gltf, {image});
    gltf.document["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                                               {"extensions", {{"KHR_materials_unlit", json::object()}}}}});
    gltf.document["extensionsUsed"] = {"KHR_materials_unlit"};
    gltf.node({{"mesh", textured_quad(gltf)}});
    test::ProbeImage image_out = test::render_gltf(gltf.write("unlit.gltf"), no_light);
    EXPECT_TRUE(is_red(at_world(image_out, -0.5f, 0.0f)));
    EXPECT_TRUE(is_green(at_world(image_out, 0.5f, 0.0f)));
}

// Occlusion darkens the ambient term only: under ambient light alone, the occluded half is black.
TEST(GltfMaterialMaps, OcclusionTextureDarkensTheAmbientTerm) {
    std::string image = test::write_test_png("occlusion.png", 2, 2, {kBlack, kWhite, kBlack, kWhite});
    auto build = [&](const std::string& name, double strength) {
        GltfBuilder gltf;
        add_textures(gltf, {image});
        gltf.document["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
                          {"occlusionTexture", {{"index", 0}, {"strength", strength}}}}});
        gltf.node({{"mesh", textured_quad(gltf)}});
        return gltf.write(name);
    };
    auto ambient_only = [](Scene& scene) {
        scene.lights.clear();
        scene.ambient_light = glm::vec3(0.5f);
        scene.environment.color = glm::vec3(0.0f);
    };
    test::ProbeImage full = test::render_gltf(build("occlusion.gltf", 1.0), ambient_only);
    EXPECT_LT(at_world(full, -0.5f, 0.0f).r, 30);  // unoccluded: 188
    EXPECT_GT(at_world(full, 0.5f, 0.0f).r, 150);
    test::ProbeImage half = test::render_gltf(build("occlusion_half.gltf", 0.5), ambient_only);
    EXPECT_GT(at_world(half, -0.5f, 0.0f).r, 100);  // strength 0.5: half the ambient light
    EXPECT_LT(at_world(half, -0.5f, 0.0f).r, at_world(full, 0.5f, 0.0f).r - 20);
}

// A normal map tilting every normal 37 degrees towards +x (+u): a light low on the +x side lights the quad more
// than the flat quad gets, one low on the -x side not at all. Generated tangents give the file's own.
TEST(GltfMaterialMaps, NormalMapTiltsTheShadingNormal) {
    // (0.6, 0, 0.8) encoded as (n + 1) / 2.
    std::string image = test::write_test_png("normal_tilt.png", 1, 1, {0xffe680ccu});
    auto build = [&](const std::string& name, bool normal_map, bool tangents) {
        GltfBuilder gltf;
        add_textures(gltf, {image});
        json material = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}}};
        if (normal_map) material["normalTexture"] = {{"index", 0}};
        gltf.document["materials"] = json::array({material});
        gltf.node({{"mesh", textured_quad(gltf, tangents)}});
        return gltf.write(name);
    };
    auto light_from = [](float side) {
        return [side](Scene& scene) {
            scene.lights.clear();
            Light light;
            light.type = LightType::Directional;
            light.direction = glm::normalize(glm::vec3(-side, 0.0f, -0.25f));  // the way the light travels
            scene.lights.push_back(light);
            scene.ambient_light = glm::vec3(0.0f);
            scene.environment.color = glm::vec3(0.0f);
        };
    };
    test::Rgb flat = test::render_gltf(build("normal_flat.gltf", false, true), light_from(1.0f)).at_ndc(0.0f, 0.0f);
    test::ProbeImage lit = test::render_gltf(build("normal_lit.gltf", true, true), light_from(1.0f));
    test::Rgb dark = test::render_gltf(build("normal_dark.gltf", true, true), light_from(-1.0f)).at_ndc(0.0f, 0.0f);
    EXPECT_GT(lit.at_ndc(0.0f, 0.0f).r, flat.r + 50);
    EXPECT_LT(dark.r, 10);
    EXPECT_GT(flat.r, 60);
    test::ProbeImage generated = test::render_gltf(build("normal_generated.gltf", true, false), light_from(1.0f));
    EXPECT_GE(test::psnr_rgba8(lit.frame.image, generated.frame.image), 50.0);
}

// alphaMode MASK cuts the quad out where the base texture's alpha is below the cutoff (the green sky shows);
// BLEND lets 1 - alpha of the sky through, unrefracted.
TEST(GltfMaterialMaps, AlphaMaskCutsOutAndBlendMixes) {
    auto build = [](const std::string& name, json mode_and_factor, bool textured) {
        GltfBuilder gltf = alpha_quad(mode_and_factor, textured);
        gltf.node({{"mesh", textured_quad(gltf)}});
        return gltf.write(name);
    };
    auto green_sky = [](Scene& scene) {
        scene.lights.clear();
        scene.ambient_light = glm::vec3(1.0f);
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = glm::vec3(0.0f, 1.0f, 0.0f);
    };
    test::ProbeImage mask =
        test::render_gltf(build("alpha_mask.gltf", {{"mode", "MASK"}, {"factor", {1, 1, 1, 1}}}, true), green_sky);
    test::Rgb cut = at_world(mask, -0.5f, 0.0f), solid = at_world(mask, 0.5f, 0.0f);
    EXPECT_LT(cut.r, 10);
    EXPECT_GT(cut.g, 240);
    EXPECT_GT(solid.r, 230);
    EXPECT_LT(solid.g, 60);  // a dielectric: Fresnel reflects a little of the sky even head-on
    // OPAQUE ignores alpha: both halves are red.
    test::ProbeImage opaque =
        test::render_gltf(build("alpha_opaque.gltf", {{"mode", "OPAQUE"}, {"factor", {1, 1, 1, 1}}}, true), green_sky);
    EXPECT_GT(at_world(opaque, -0.5f, 0.0f).r, 230);
    // BLEND at alpha 0.5: half red, half sky (linear), so both channels sit near sRGB 188.
    test::ProbeImage blend =
        test::render_gltf(build("alpha_blend.gltf", {{"mode", "BLEND"}, {"factor", {1, 0, 0, 0.5}}}, false), green_sky);
    test::Rgb mixed = blend.at_ndc(0.0f, 0.0f);
    EXPECT_NEAR(mixed.r, 188, 6);
    EXPECT_NEAR(mixed.g, 188, 6);
}

// The material tests whose kernels paths no agreement scene exercises, on every backend (Vulkan under the
// validation layer).
class EveryBackend : public ::testing::TestWithParam<std::string> {
protected:
    void SetUp() override {
        std::string reason;
        if (!test::backend_spec_runs_here(GetParam(), &reason)) GTEST_SKIP() << reason;
        test::begin_backend_checks(GetParam());
    }
    void TearDown() override {
        if (IsSkipped()) return;
        std::vector<std::string> messages = test::backend_check_messages(GetParam());
        EXPECT_TRUE(messages.empty()) << (messages.empty() ? "" : messages.front());
    }
};

// Shadows through cut-outs: a MASK quad half cut out, half above the cutoff, floats 0.5 in front of a white
// floor, lit along -z. Through the cut-out half the camera sees the floor lit (the shadow ray passes the cut-out as
// the camera ray did); a BLEND quad at alpha 0.5 lets half the light through to the floor behind it. These shadow
// rays are the shadow_layers stage's (kernels/stages.h), a kernel of its own that no other test scene launches.
TEST_P(EveryBackend, ShadowRaysPassCutOutsAndBlendedSurfaces) {
    auto build = [](const std::string& name, json mode_and_factor, bool textured) {
        GltfBuilder gltf = alpha_quad(mode_and_factor, textured);
        gltf.document["materials"].push_back(  // material 1: a white floor that does not mirror
            {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
             {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}});
        gltf.node({{"mesh", textured_quad(gltf)}, {"translation", {0, 0, 0.5}}});
        const int floor = textured_quad(gltf);
        gltf.document["meshes"][floor]["primitives"][0]["material"] = 1;
        gltf.node({{"mesh", floor}, {"scale", {3, 3, 1}}});
        return gltf.write(name);
    };
    auto light_along_minus_z = [](Scene& scene) {
        scene.lights.clear();
        Light sun;
        sun.type = LightType::Directional;
        sun.direction = {0.0f, 0.0f, -1.0f};
        scene.lights.push_back(sun);
        scene.ambient_light = glm::vec3(0.0f);
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = glm::vec3(0.0f);
    };
    // The floor point (-0.5, 0, 0) is seen through the cut-out half; its shadow ray leaves along +z through it.
    test::ProbeImage mask = test::render_gltf(build("shadow_mask-" + test::test_name_of(GetParam()) + ".gltf",
                                                    {{"mode", "MASK"}, {"factor", {1, 1, 1, 1}}}, true),
                                              light_along_minus_z, 64, 4, GetParam());
    test::Rgb through = at_world(mask, -0.5f, 0.0f);
    EXPECT_GT(through.r, 200) << "the floor behind a cut-out is lit";
    EXPECT_GT(through.g, 200);
    EXPECT_GT(at_world(mask, 0.5f, 0.0f).r, 200);  // the solid half: red, lit
    EXPECT_LT(at_world(mask, 0.5f, 0.0f).g, 60);
    // BLEND at alpha 0.5: half the quad's red over the floor, which gets half the light (sRGB of 0.5 is 188).
    test::ProbeImage blend = test::render_gltf(build("shadow_blend-" + test::test_name_of(GetParam()) + ".gltf",
                                                     {{"mode", "BLEND"}, {"factor", {1, 0, 0, 0.5}}}, false),
                                               light_along_minus_z, 64, 4, GetParam());
    test::Rgb mixed = blend.at_ndc(0.0f, 0.0f);
    // Linear: red 0.5 (the quad) + 0.5 x 0.5 (the floor, half lit) = 0.75; green and blue 0.25.
    EXPECT_NEAR(mixed.r, 225, 8);
    EXPECT_NEAR(mixed.g, 137, 8);
    EXPECT_NEAR(mixed.b, 137, 8);
    // The shadow_layers stage (kernels/stage_list.h: needs RT_FLAG_ALPHA_SHADOWS) traced them, once per depth.
    if (GetParam() != "cpu-ref") {
        size_t launches = 0;
        for (const StageTiming& t : blend.frame.stats.stages) launches += t.stage == Stage::ShadowLayers;
        EXPECT_EQ(launches, 4u);
    }
}

// An opaque dielectric mirrors a bright sky by Schlick's Fresnel: a few % head-on, far more at a grazing angle;
// KHR_materials_specular's specularFactor 0 turns the reflection off.
TEST(GltfMaterialMaps, OpaqueDielectricsReflectMoreAtGrazingAngles) {
    auto build = [&](const std::string& name, double tilt_degrees, json extensions) {
        GltfBuilder gltf;
        json material = {{"pbrMetallicRoughness",
                          {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}}};
        if (!extensions.is_null()) material["extensions"] = extensions;
        gltf.document["materials"] = json::array({material});
        add_tilted_quad(gltf, tilt_degrees);
        return gltf.write(name);
    };
    test::Rgb head_on = test::render_gltf(build("fresnel_head_on.gltf", 0.0, nullptr), white_sky).at_ndc(0.0f, 0.0f);
    test::Rgb grazing = test::render_gltf(build("fresnel_grazing.gltf", -75.0, nullptr), white_sky).at_ndc(0.0f, 0.0f);
    EXPECT_GT(head_on.r, 30);  // F0 = 0.04: sRGB 56
    EXPECT_LT(head_on.r, 80);
    EXPECT_GT(grazing.r, head_on.r + 50);
    test::Rgb no_specular =
        test::render_gltf(build("fresnel_off.gltf", -75.0, {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}),
                          white_sky)
            .at_ndc(0.0f, 0.0f);
    EXPECT_LT(no_specular.r, 10);
}

namespace {

// An emissive-only quad (so the probes read the texture's own colours) with the given KHR_texture_transform and
// sampler on its 2x2 red/green/blue/white texture.
test::ProbeImage render_transformed(const std::string& name, json transform, json sampler,
                                    const std::string& backend = "cpu-ref") {
    std::string image = test::write_test_png("transform_rgbw.png", 2, 2, {kRed, kGreen, kBlue, kWhite});
    GltfBuilder gltf;
    add_textures(gltf, {image});
    if (!sampler.is_null()) {
        gltf.document["samplers"] = json::array({sampler});
        gltf.document["textures"][0]["sampler"] = 0;
    }
    json texture = {{"index", 0}};
    if (!transform.is_null()) texture["extensions"] = {{"KHR_texture_transform", transform}};
    gltf.document["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                      {"emissiveFactor", {1, 1, 1}},
                      {"emissiveTexture", texture}}});
    gltf.node({{"mesh", textured_quad(gltf)}});
    return test::render_gltf(gltf.write(name), no_light, 96, 4, backend);
}

// uv scaled by 3 and moved to [-3.25, -0.25], nearest texels: every texel coordinate is negative, where GLSL leaves %
// undefined (kernels/texture.h, rt_wrap_repeat); each backend wraps them as cpu-ref does, repeat and mirrored.
TEST_P(EveryBackend, NegativeTexelCoordinatesWrapAsOnTheHost) {
    json transform = {{"offset", {-3.25, -2.5}}, {"scale", {3.0, 3.0}}};
    for (int wrap : {10497, 33648}) {
        json sampler = {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", wrap}, {"wrapT", wrap}};
        std::string name = "negative_wrap_" + std::to_string(wrap) + "-" + test::test_name_of(GetParam()) + ".gltf";
        test::ProbeImage expected = render_transformed(name, transform, sampler);
        test::ProbeImage actual = render_transformed(name, transform, sampler, GetParam());
        EXPECT_GE(test::psnr_rgba8(expected.frame.image, actual.frame.image), 50.0) << "wrap " << wrap;
    }
}

// glTF doubleSided: an emissive red quad turned to face away from the camera, 0.5 in front of an emissive green one.
// Single-sided, its back is not seen and the green one shows through (with a faint reflection of the red front);
// double-sided, it hides it. A refracting single-sided quad keeps its back faces (a ray inside glass leaves through
// them): it tints the green.
TEST_P(EveryBackend, BackFacesOfSingleSidedSurfacesAreNotSeen) {
    auto build = [&](const std::string& name, bool double_sided, bool refracting) {
        GltfBuilder gltf;
        json red = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0}}},
                    {"emissiveFactor", {1, 0, 0}},
                    {"doubleSided", double_sided}};
        if (refracting) red["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}};
        gltf.document["materials"] =
            json::array({red,
                         {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                          {"emissiveFactor", {0, 1, 0}}}});
        const int front = textured_quad(gltf);
        const int back = textured_quad(gltf);
        gltf.document["meshes"][back]["primitives"][0]["material"] = 1;
        gltf.node({{"mesh", front}, {"translation", {0, 0, 0.5}}, {"rotation", {0, 1, 0, 0}}});  // 180 degrees about y
        gltf.node({{"mesh", back}, {"scale", {2, 2, 1}}});
        return gltf.write(name + "-" + test::test_name_of(GetParam()) + ".gltf");
    };
    test::Rgb single = test::render_gltf(build("single_sided", false, false), no_light, 64, 4, GetParam()).at_ndc(0, 0);
    EXPECT_LT(single.r, 60);  // the green quad mirrors a little of the red one's front (F0 = 0.04)
    EXPECT_GT(single.g, 200);
    test::Rgb both = test::render_gltf(build("double_sided", true, false), no_light, 64, 4, GetParam()).at_ndc(0, 0);
    EXPECT_GT(both.r, 200);
    EXPECT_LT(both.g, 20);
    test::Rgb glass =
        test::render_gltf(build("single_sided_glass", false, true), no_light, 64, 4, GetParam()).at_ndc(0, 0);
    EXPECT_NE(glass.r, single.r) << "a refracting back face is still met";
}

INSTANTIATE_TEST_SUITE_P(Backends, EveryBackend,
                         ::testing::Values("cpu-ref", "cpu", "cuda", test::test_device("opencl"),
                                           test::test_device("vulkan")),
                         [](const auto& info) { return test::test_name_of(info.param); });

}  // namespace

// A quarter turn: the Khronos sample viewer maps (u, v) to (cos u + sin v, -sin u + cos v) = (v, -u), so the
// top-left quarter of the quad shows the texture's bottom-left texel (blue) and the top-right its top-left (red).
// The other sign would show green top-left.
TEST(GltfMaterialMaps, TextureTransformRotatesAsTheSampleViewer) {
    test::ProbeImage image = render_transformed("rotated.gltf", {{"rotation", 1.5707963}}, nullptr);
    EXPECT_TRUE(is_blue(at_world(image, -0.5f, 0.5f)));
    EXPECT_TRUE(is_red(at_world(image, 0.5f, 0.5f)));
    test::ProbeImage plain = render_transformed("unrotated.gltf", nullptr, nullptr);
    EXPECT_TRUE(is_red(at_world(plain, -0.5f, 0.5f)));
    EXPECT_TRUE(is_green(at_world(plain, 0.5f, 0.5f)));
}

// u scaled by 2 (the quad's right half samples u in [1, 2]), nearest texels: repeat starts the texture again,
// clamp-to-edge holds the last column, mirrored repeat runs it backwards.
TEST(GltfMaterialMaps, SamplerWrapModesAndNearestFilter) {
    json scale = {{"scale", {2.0, 1.0}}};
    auto render = [&](const std::string& name, int wrap) {
        return render_transformed(name, scale,
                                  {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", wrap}, {"wrapT", 10497}});
    };
    test::ProbeImage repeat = render("wrap_repeat.gltf", 10497);
    test::ProbeImage clamp = render("wrap_clamp.gltf", 33071);
    test::ProbeImage mirror = render("wrap_mirror.gltf", 33648);
    // u' = 1.375 and 1.875 on the top row (red, green).
    EXPECT_TRUE(is_red(at_world(repeat, 0.375f, 0.5f)));
    EXPECT_TRUE(is_green(at_world(repeat, 0.875f, 0.5f)));
    EXPECT_TRUE(is_green(at_world(clamp, 0.375f, 0.5f)));
    EXPECT_TRUE(is_green(at_world(clamp, 0.875f, 0.5f)));
    EXPECT_TRUE(is_green(at_world(mirror, 0.375f, 0.5f)));
    EXPECT_TRUE(is_red(at_world(mirror, 0.875f, 0.5f)));
    // Nearest: no blend at a texel border (u' = 0.5 lies between red and green; probe just left of it).
    test::Rgb edge = at_world(repeat, -0.52f, 0.5f);
    EXPECT_TRUE(is_red(edge) || is_green(edge));
}

// KHR_materials_specular's textures: specularTexture's alpha scales the Fresnel term (left column 0: no
// reflection), specularColorTexture tints the reflection.
TEST(GltfMaterialMaps, SpecularTexturesScaleAndTintTheReflection) {
    constexpr uint32_t kClearWhite = 0x00ffffffu;
    std::string strength = test::write_test_png("specular_alpha.png", 2, 2, {kClearWhite, kWhite, kClearWhite, kWhite});
    std::string tint = test::write_test_png("specular_red.png", 1, 1, {kRed});
    auto build = [&](const std::string& name, bool tinted) {
        GltfBuilder gltf;
        add_textures(gltf, {strength, tint});
        json specular = {{"specularTexture", {{"index", 0}}}};
        if (tinted) specular["specularColorTexture"] = {{"index", 1}};
        gltf.document["materials"] =
            json::array({{{"pbrMetallicRoughness",
                           {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
                          {"extensions", {{"KHR_materials_specular", specular}}}}});
        add_tilted_quad(gltf, -75.0);
        return gltf.write(name);
    };
    test::ProbeImage plain = test::render_gltf(build("specular_texture.gltf", false), white_sky, 96);
    EXPECT_LT(at_world(plain, -0.5f, 0.0f).r, 10);
    EXPECT_GT(at_world(plain, 0.5f, 0.0f).r, 80);
    test::ProbeImage tinted = test::render_gltf(build("specular_color_texture.gltf", true), white_sky, 96);
    test::Rgb red = at_world(tinted, 0.5f, 0.0f);
    EXPECT_GT(red.r, 80);
    EXPECT_LT(red.g, 10);
}

}  // namespace prism
