// KHR_materials_pbrSpecularGlossiness (archived by Khronos, still in many older assets: Sketchfab's and Blender's
// exports of a few years ago) converted to metallic-roughness, which the rest of the glTF path maps onto Prism's
// material. Without it such a model has no base colour and renders white. The conversion solves for the metallic
// value that reproduces the diffuse and specular colours under the metal-rough model's split (a dielectric's
// specular is 0.04; a metal's is its base colour), per material and, where there are textures, per texel.
#pragma once

#include <string>
#include <utility>

#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace prism::gltf {

struct SpecularGlossiness {
    glm::vec4 diffuse{1.0f};   // linear RGB and alpha
    glm::vec3 specular{1.0f};  // linear F0
    float glossiness = 1.0f;
};

struct MetallicRoughness {
    glm::vec4 base{1.0f};
    float metallic = 0.0f;
    float roughness = 0.0f;
};

MetallicRoughness metallic_roughness_of(const SpecularGlossiness& material);

// The textures of a converted material: base colour (sRGB RGBA) and metallic-roughness (linear; G roughness,
// B metallic), at the larger of the two inputs' sizes, each input sampled at the same place (exporters give both
// one set of texture coordinates). `diffuse` (sRGB RGBA) and `specular_glossiness` (sRGB RGB, linear alpha) may
// each be null (the factor alone); the factors multiply the texels, so the converted material's factors are 1.
std::pair<Texture, Texture> metallic_roughness_textures(const SpecularGlossiness& factors, const Texture* diffuse,
                                                        const Texture* specular_glossiness, const std::string& name);

}  // namespace prism::gltf
