// KHR_materials_volume: Beer-Lambert attenuation over the distance a ray travels inside a solid medium, checked on
// rendered pixels of a generated glass cube in front of a white sky.
#include <gtest/gtest.h>

#include "tests/gltf_builder.h"
#include "tests/gltf_render_probe.h"

namespace prism {
namespace {

using nlohmann::json;
using test::GltfBuilder;

// A closed unit cube (faces wound outwards) of non-refracting glass (ior 1) absorbing to attenuationColor 0.5
// after `distance`.
std::filesystem::path glass_cube(const std::string& name, double distance) {
    GltfBuilder gltf;
    int positions = gltf.positions({-0.5f, -0.5f, -0.5f, 0.5f, -0.5f, -0.5f, 0.5f, 0.5f, -0.5f, -0.5f, 0.5f, -0.5f,
                                    -0.5f, -0.5f, 0.5f,  0.5f, -0.5f, 0.5f,  0.5f, 0.5f, 0.5f,  -0.5f, 0.5f, 0.5f});
    int indices = gltf.indices(
        {4, 5, 6, 4, 6, 7, 0, 2, 1, 0, 3, 2, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3, 3, 7, 6, 3, 6, 2, 0, 1, 5, 0, 5, 4});
    json volume = {{"thicknessFactor", 1.0}, {"attenuationColor", {0.5, 0.5, 0.5}}};
    if (distance > 0) volume["attenuationDistance"] = distance;
    gltf.document["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}}},
                      {"extensions",
                       {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                        {"KHR_materials_ior", {{"ior", 1.0}}},
                        {"KHR_materials_volume", volume}}}}});
    gltf.node({{"mesh", gltf.mesh(json::array(
                            {{{"attributes", {{"POSITION", positions}}}, {"indices", indices}, {"material", 0}}}))}});
    return gltf.write(name);
}

void white_sky(Scene& scene) {
    scene.lights.clear();
    scene.ambient_light = glm::vec3(0.0f);
    scene.environment.kind = EnvironmentKind::Constant;
    scene.environment.color = glm::vec3(1.0f);
}

}  // namespace

// Through one unit of glass: 0.5^(1 / distance) of the sky; a row of growing distances brightens monotonically,
// and no distance (infinite) absorbs nothing.
TEST(GltfVolume, AttenuationFollowsBeerLambertOverTheDistanceInside) {
    std::vector<int> row;
    for (double distance : {0.25, 0.5, 1.0, 2.0, 4.0}) {
        test::ProbeImage image =
            test::render_gltf(glass_cube("cube_" + std::to_string(distance) + ".gltf", distance), white_sky, 48, 6);
        row.push_back(image.at_ndc(0.0f, 0.0f).r);
    }
    for (size_t i = 1; i < row.size(); ++i) EXPECT_GT(row[i], row[i - 1] + 5) << "distance index " << i;
    EXPECT_NEAR(row[2], 188, 6);  // distance 1: linear 0.5
    test::ProbeImage clear = test::render_gltf(glass_cube("cube_clear.gltf", 0.0), white_sky, 48, 6);
    EXPECT_GT(clear.at_ndc(0.0f, 0.0f).r, 250);
}

}  // namespace prism
