// glTF PBR materials (metallic-roughness and the KHR_materials_* / KHR_texture_transform extensions) mapped onto the
// seed's Whitted material (core/scene/scene.h Material). Every mapping is written down in docs/materials.md.
#pragma once

#include <map>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace tinygltf {
class Model;
class Value;
}  // namespace tinygltf

namespace prism::gltf {

// Converts glTF materials into one scene, decoding each base-colour texture once.
class MaterialConverter {
public:
    MaterialConverter(const tinygltf::Model& model, std::string file, Scene& scene);

    // Index in scene.materials of glTF material `index` (converted on first use); -1 gives the default material.
    uint32_t material(int index);

private:
    Material convert(int index);
    // Index in scene.textures of glTF texture `index`, decoded as sRGB colour or as linear data; throws when its
    // image is missing. Returns false (with a warning) when the texture has no image Prism can decode.
    bool texture(int index, bool color_data, uint32_t& scene_texture);
    // glTF texture `index` decoded, without adding it to the scene; nullopt (with a warning) when it has no image
    // Prism can decode.
    std::optional<Texture> decode(int index, bool color_data);
    // A material's texture reference (texture, texCoord, KHR_texture_transform) as a layer; nothing when the
    // reference is absent or its image undecodable.
    // `transform` is the reference's KHR_texture_transform object, if any.
    std::optional<TextureLayer> layer(int index, int tex_coord, const tinygltf::Value* transform, bool color_data,
                                      const std::string& material_name);
    // Scene texture `scene_texture` placed as glTF texture `index` is referenced: its sampler, texCoord, transform.
    TextureLayer placed(uint32_t scene_texture, int index, int tex_coord, const tinygltf::Value* transform,
                        const std::string& material_name);
    // KHR_materials_pbrSpecularGlossiness converted to the metallic-roughness fields of `material`
    // (gltf_spec_gloss.h): diffuse, alpha, metallic, roughness, the base-colour layer and metal_rough_map.
    void apply_specular_glossiness(const tinygltf::Value& extension, Material& material);

    const tinygltf::Model& model_;
    std::string file_;
    Scene& scene_;
    std::map<int, uint32_t> materials_;
    std::map<std::pair<int, bool>, uint32_t> textures_;  // (glTF texture, colour data) -> scene texture
};

// KHR_materials_dispersion: per-channel IOR (red, green, blue) from the IOR at the d line (587.6 nm) and
// `dispersion` = 20 / Abbe number, through Cauchy's n = A + B / lambda^2 (the extension's model).
glm::vec3 dispersive_ior(float ior, float dispersion);

// The thin-shell thickness (metres, glTF's unit) given to thin-walled transmissive glTF surfaces.
inline constexpr float kThinWalledThickness = 0.001f;

}  // namespace prism::gltf
