#include "core/loaders/gltf_spec_gloss.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/util/scene_read_rules.h"

namespace prism::gltf {
namespace {

constexpr float kDielectricSpecular = 0.04f;
constexpr float kEpsilon = 1e-6f;

// Brightness as the eye weighs the channels (Rec. 601 luma weights on squared values).
float perceived(glm::vec3 c) { return std::sqrt(0.299f * c.x * c.x + 0.587f * c.y * c.y + 0.114f * c.z * c.z); }

// The metallic value m for which a material of diffuse brightness `diffuse` and specular brightness `specular`
// has the same specular under the metal-rough split: specular = 0.04 (1 - m) + base m, with the diffuse energy
// that is left, a quadratic in m.
float solve_metallic(float diffuse, float specular, float one_minus_specular_strength) {
    if (specular < kDielectricSpecular) return 0.0f;
    const float a = kDielectricSpecular;
    const float b = diffuse * one_minus_specular_strength / (1.0f - a) + specular - 2.0f * a;
    const float c = a - specular;
    const float discriminant = std::max(0.0f, b * b - 4.0f * a * c);
    return std::clamp((-b + std::sqrt(discriminant)) / (2.0f * a), 0.0f, 1.0f);
}

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float linear_to_srgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

uint8_t byte_of(float value) { return uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }
float channel(uint32_t texel, int k) { return float(texel >> (8 * k) & 255u) / 255.0f; }

// Tables for the texel loop: a 4096x4096 texture pair is 16M texels, and three powers a texel each way took
// seconds. 8-bit sRGB in; linear out at a step well under one 8-bit sRGB level even near black.
struct SrgbTables {
    static constexpr int kLinearSteps = 1 << 16;
    std::array<float, 256> to_linear;
    std::vector<uint8_t> to_srgb;
    SrgbTables() : to_srgb(kLinearSteps + 1) {
        for (int i = 0; i < 256; ++i) to_linear[i] = srgb_to_linear(float(i) / 255.0f);
        for (int i = 0; i <= kLinearSteps; ++i) to_srgb[i] = byte_of(linear_to_srgb(float(i) / kLinearSteps));
    }
    float linear(uint32_t texel, int k) const { return to_linear[texel >> (8 * k) & 255u]; }
    uint32_t srgb(float linear) const {
        return to_srgb[size_t(std::lround(std::clamp(linear, 0.0f, 1.0f) * kLinearSteps))];
    }
};

// The texel at (x, y) of a width x height grid laid over `texture` (nearest), or white without a texture.
uint32_t texel_at(const Texture* texture, int x, int y, int width, int height) {
    if (!texture || texture->texels.empty()) return 0xffffffffu;
    const int tx = std::min(texture->width - 1, int((x + 0.5f) * texture->width / width));
    const int ty = std::min(texture->height - 1, int((y + 0.5f) * texture->height / height));
    return texture->texels[size_t(ty) * size_t(texture->width) + size_t(tx)];
}

}  // namespace

MetallicRoughness metallic_roughness_of(const SpecularGlossiness& material) {
    const glm::vec3 diffuse = glm::clamp(glm::vec3(material.diffuse), 0.0f, 1.0f);
    const glm::vec3 specular = glm::clamp(material.specular, 0.0f, 1.0f);
    const float one_minus_specular_strength = 1.0f - std::max(specular.x, std::max(specular.y, specular.z));
    MetallicRoughness out;
    out.metallic = solve_metallic(perceived(diffuse), perceived(specular), one_minus_specular_strength);
    const glm::vec3 from_diffuse = diffuse * (one_minus_specular_strength / (1.0f - kDielectricSpecular) /
                                              std::max(1.0f - out.metallic, kEpsilon));
    const glm::vec3 from_specular =
        (specular - glm::vec3(kDielectricSpecular * (1.0f - out.metallic))) / std::max(out.metallic, kEpsilon);
    out.base = glm::vec4(glm::clamp(glm::mix(from_diffuse, from_specular, out.metallic * out.metallic), 0.0f, 1.0f),
                         material.diffuse.w);
    out.roughness = std::clamp(1.0f - material.glossiness, 0.0f, 1.0f);
    return out;
}

std::pair<Texture, Texture> metallic_roughness_textures(const SpecularGlossiness& factors, const Texture* diffuse,
                                                        const Texture* specular_glossiness, const std::string& name) {
    const int width = std::max(diffuse ? diffuse->width : 1, specular_glossiness ? specular_glossiness->width : 1);
    const int height = std::max(diffuse ? diffuse->height : 1, specular_glossiness ? specular_glossiness->height : 1);
    Texture base{name + " (base colour from specular-glossiness)", width, height, TextureEncoding::Srgb8, {}};
    Texture metal_rough{
        name + " (metallic-roughness from specular-glossiness)", width, height, TextureEncoding::Linear8, {}};
    charge_texture_bytes(base.name, uint64_t(width) * uint64_t(height) * sizeof(uint32_t) * 2);
    base.texels.resize(size_t(width) * size_t(height));
    metal_rough.texels.resize(base.texels.size());
    static const SrgbTables tables;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint32_t d = texel_at(diffuse, x, y, width, height);
            const uint32_t s = texel_at(specular_glossiness, x, y, width, height);
            SpecularGlossiness texel;
            for (int k = 0; k < 3; ++k) {
                texel.diffuse[k] = factors.diffuse[k] * tables.linear(d, k);
                texel.specular[k] = factors.specular[k] * tables.linear(s, k);
            }
            texel.diffuse.w = factors.diffuse.w * channel(d, 3);
            texel.glossiness = factors.glossiness * channel(s, 3);
            const MetallicRoughness converted = metallic_roughness_of(texel);
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            base.texels[i] = tables.srgb(converted.base.x) | tables.srgb(converted.base.y) << 8 |
                             tables.srgb(converted.base.z) << 16 | uint32_t(byte_of(converted.base.w)) << 24;
            metal_rough.texels[i] =
                uint32_t(byte_of(converted.roughness)) << 8 | uint32_t(byte_of(converted.metallic)) << 16 | 0xff000000u;
        }
    return {std::move(base), std::move(metal_rough)};
}

}  // namespace prism::gltf
