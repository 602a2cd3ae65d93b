#include "core/loaders/gltf_material.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <tiny_gltf.h>

#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/loaders/gltf_spec_gloss.h"
#include "core/scene/seed_material.h"

namespace prism::gltf {
namespace {

const tinygltf::Value* extension(const tinygltf::ExtensionMap& extensions, const char* name) {
    auto it = extensions.find(name);
    return it == extensions.end() ? nullptr : &it->second;
}

double number(const tinygltf::Value* object, const char* key, double fallback) {
    if (!object || !object->IsObject() || !object->Has(key)) return fallback;
    const tinygltf::Value& value = object->Get(key);
    return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
}

// An array of N numbers under `key`, or `fallback` when it is missing, shorter or not all numbers.
template <int N>
glm::vec<N, float> vector_of(const tinygltf::Value* object, const char* key, glm::vec<N, float> fallback) {
    if (!object || !object->IsObject() || !object->Has(key)) return fallback;
    const tinygltf::Value& value = object->Get(key);
    if (!value.IsArray() || value.ArrayLen() < N) return fallback;
    glm::vec<N, float> result;
    for (int i = 0; i < N; ++i) {
        if (!value.Get(i).IsNumber()) return fallback;
        result[i] = static_cast<float>(value.Get(i).GetNumberAsDouble());
    }
    return result;
}

glm::vec2 vec2_of(const tinygltf::Value* object, const char* key, glm::vec2 fallback) {
    return vector_of<2>(object, key, fallback);
}
glm::vec3 vec3_of(const tinygltf::Value* object, const char* key, glm::vec3 fallback) {
    return vector_of<3>(object, key, fallback);
}
glm::vec4 vec4_of(const tinygltf::Value* object, const char* key, glm::vec4 fallback) {
    return vector_of<4>(object, key, fallback);
}

// An index or count under `key` as an int: `fallback` when missing, -1 when it is no integer in int's range (a
// cast of 1e300 to int is undefined).
int int_of(const tinygltf::Value* object, const char* key, int fallback) {
    const double value = number(object, key, double(fallback));
    return value >= double(INT32_MIN) && value <= double(INT32_MAX) && value == std::floor(value) ? int(value) : -1;
}

glm::vec3 first3(const std::vector<double>& values, glm::vec3 fallback) {
    if (values.size() < 3) return fallback;
    return {static_cast<float>(values[0]), static_cast<float>(values[1]), static_cast<float>(values[2])};
}

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) (u, v, 1), the spec's matrix order; rows 0 and 1 of
// that 3x3 are what TextureLayer stores. R is the rotation the Khronos sample viewer applies, u' = c u + s v,
// v' = -s u + c v: with v pointing down the image, that turns the texture counter-clockwise on screen as the
// extension says. Reading the spec's GLSL `mat3(cos, sin, 0, -sin, cos, 0, ...)` row by row gives the
// transpose, which turns it the other way (KhronosGroup/glTF issue 1563; TextureTransformTest's red marker).
void apply_texture_transform(const tinygltf::Value* transform, TextureLayer& layer) {
    if (!transform) return;
    glm::vec2 offset = vec2_of(transform, "offset", {0.0f, 0.0f});
    glm::vec2 scale = vec2_of(transform, "scale", {1.0f, 1.0f});
    float rotation = static_cast<float>(number(transform, "rotation", 0.0));
    float c = std::cos(rotation), s = std::sin(rotation);
    layer.uv_row0 = {scale.x * c, scale.y * s, offset.x};
    layer.uv_row1 = {-scale.x * s, scale.y * c, offset.y};
    if (transform->IsObject() && transform->Has("texCoord") && transform->Get("texCoord").IsNumber())
        layer.uv_set = static_cast<uint32_t>(std::max(0, transform->Get("texCoord").GetNumberAsInt()));
}

// A textureInfo inside an extension object (its index, texCoord and KHR_texture_transform); index -1 when absent.
struct TextureRef {
    int index = -1;
    int tex_coord = 0;
    const tinygltf::Value* transform = nullptr;
};

TextureRef texture_ref(const tinygltf::Value* object, const char* key) {
    TextureRef ref;
    if (!object || !object->IsObject() || !object->Has(key)) return ref;
    const tinygltf::Value& info = object->Get(key);
    ref.index = int_of(&info, "index", -1);
    ref.tex_coord = std::max(0, int_of(&info, "texCoord", 0));
    if (info.IsObject() && info.Has("extensions") && info.Get("extensions").IsObject() &&
        info.Get("extensions").Has("KHR_texture_transform"))
        ref.transform = &info.Get("extensions").Get("KHR_texture_transform");
    return ref;
}

// KHR_materials_specular's Fresnel: specularFactor k scales the whole Schlick term,
// F = k (F0 + (1 - F0) (1 - cos)^5) with F0 from the IOR, so k = 0 turns the dielectric reflection off.
void set_specular_fresnel(Material& material, float ior, float k) {
    float f0 = std::min(1.0f, schlick_f0(ior));
    k = std::clamp(k, 0.0f, 1.0f);
    set_dielectric_fresnel(material, f0 * k);
    material.fresnel_scale = (1.0f - f0) * k;
}

// KHR_materials_unlit (scans and baked-lighting assets): the surface shows its base colour (times the base colour
// texture) whatever lights it, and reflects nothing. In the seed's model that is an emitter without diffuse or
// specular terms; the base colour layer stays in the texture stack for its alpha (cut-outs, blending). COLOR_0 is
// not applied to the emission.
void make_unlit(Material& material, glm::vec4 base) {
    material.emissive = glm::vec3(base);
    material.emissive_map.reset();
    if (!material.textures.empty()) material.emissive_map = material.textures.front();
    material.diffuse = glm::vec3(0.0f);
    material.metallic = 0.0f;
    material.reflectivity = 0.0f;
    material.transmittance = 0.0f;
    material.metal_rough_map.reset();
    material.normal_map.reset();
    material.occlusion_map.reset();
    material.specular_map.reset();
    material.specular_color_map.reset();
    material.iridescence = 0.0f;
    material.iridescence_map.reset();
    material.iridescence_thickness_map.reset();
    material.clearcoat = 0.0f;
    material.clearcoat_map.reset();
    material.clearcoat_roughness_map.reset();
    set_specular_fresnel(material, 1.5f, 0.0f);  // a Fresnel term of 0: no reflection at any angle
}

TextureWrap wrap_mode(int gl_wrap) {
    switch (gl_wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::MirroredRepeat;
        default: return TextureWrap::Repeat;
    }
}

// The texture's sampler (none: repeat, bilinear). Prism builds no mipmaps, so only the magnification filter
// decides between nearest and bilinear.
void apply_sampler(const tinygltf::Model& model, int sampler, TextureLayer& layer) {
    if (sampler < 0 || sampler >= static_cast<int>(model.samplers.size())) return;
    const tinygltf::Sampler& source = model.samplers[sampler];
    layer.wrap_u = wrap_mode(source.wrapS);
    layer.wrap_v = wrap_mode(source.wrapT);
    layer.nearest = source.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
}

}  // namespace

glm::vec3 dispersive_ior(float ior, float dispersion) {
    if (dispersion <= 0.0f) return glm::vec3(ior);
    // Fraunhofer F, C and d lines (micrometres) define the Abbe number V = (n_d - 1) / (n_F - n_C).
    const double lambda_f = 0.4861, lambda_c = 0.6563, lambda_d = 0.5876;
    double abbe = 20.0 / dispersion;
    double b = (ior - 1.0) / (abbe * (1.0 / (lambda_f * lambda_f) - 1.0 / (lambda_c * lambda_c)));
    double a = ior - b / (lambda_d * lambda_d);
    // Representative wavelengths of Prism's red, green and blue rays.
    auto at = [&](double lambda) { return static_cast<float>(a + b / (lambda * lambda)); };
    return {at(0.65), at(0.55), at(0.45)};
}

MaterialConverter::MaterialConverter(const tinygltf::Model& model, std::string file, Scene& scene)
    : model_(model), file_(std::move(file)), scene_(scene) {}

uint32_t MaterialConverter::material(int index) {
    if (index >= static_cast<int>(model_.materials.size()))
        throw file_error(file_, "material " + std::to_string(index) + " does not exist");
    if (index < 0) index = -1;
    auto found = materials_.find(index);
    if (found != materials_.end()) return found->second;
    Material material = convert(index);
    scene_.materials.push_back(std::move(material));
    auto scene_index = static_cast<uint32_t>(scene_.materials.size() - 1);
    materials_[index] = scene_index;
    return scene_index;
}

bool MaterialConverter::texture(int index, bool color_data, uint32_t& scene_texture) {
    auto found = textures_.find({index, color_data});
    if (found != textures_.end()) {
        scene_texture = found->second;
        return true;
    }
    std::optional<Texture> decoded = decode(index, color_data);
    if (!decoded) return false;
    scene_.textures.push_back(std::move(*decoded));
    scene_texture = static_cast<uint32_t>(scene_.textures.size() - 1);
    textures_[{index, color_data}] = scene_texture;
    return true;
}

std::optional<Texture> MaterialConverter::decode(int index, bool color_data) {
    if (index < 0 || index >= static_cast<int>(model_.textures.size()))
        throw file_error(file_, "texture " + std::to_string(index) + " does not exist");
    // EXT_texture_webp's image is the texture's own (`source`, when present, is a PNG or JPEG fallback for viewers
    // without WebP); the spec asks a viewer that reads WebP to use it.
    const tinygltf::Texture& gltf_texture = model_.textures[index];
    const double webp = number(extension(gltf_texture.extensions, "EXT_texture_webp"), "source", -1.0);
    const int source = webp >= 0.0 && webp < double(model_.images.size()) ? int(webp) : gltf_texture.source;
    if (source < 0 || source >= static_cast<int>(model_.images.size())) {
        scene_.warnings.push_back(file_ + ": texture " + std::to_string(index) +
                                  " has no PNG, JPEG or WebP image (KHR_texture_basisu is not read); ignored");
        return std::nullopt;
    }
    const tinygltf::Image& image = model_.images[source];
    if (image.image.empty()) {
        if (!image.uri.empty()) throw file_error(file_, "image '" + image.uri + "' not found or empty");
        throw file_error(file_, "image " + std::to_string(source) + " has no data");
    }
    std::string name = file_ + ": " + (image.uri.empty() ? "image " + std::to_string(source) : image.uri);
    return load_texture_from_memory(std::span<const uint8_t>(image.image), name, color_data);
}

std::optional<TextureLayer> MaterialConverter::layer(int index, int tex_coord, const tinygltf::Value* transform,
                                                     bool color_data, const std::string& material_name) {
    if (index < 0) return std::nullopt;
    uint32_t scene_texture = 0;
    if (!texture(index, color_data, scene_texture)) return std::nullopt;
    return placed(scene_texture, index, tex_coord, transform, material_name);
}

TextureLayer MaterialConverter::placed(uint32_t scene_texture, int index, int tex_coord,
                                       const tinygltf::Value* transform, const std::string& material_name) {
    TextureLayer layer;
    layer.texture = scene_texture;
    layer.mode = TextureMode::Modulate;
    apply_sampler(model_, model_.textures[index].sampler, layer);
    layer.uv_set = static_cast<uint32_t>(std::max(0, tex_coord));
    apply_texture_transform(transform, layer);
    if (layer.uv_set > 1) {
        scene_.warnings.push_back(file_ + ": material '" + material_name + "' uses TEXCOORD_" +
                                  std::to_string(layer.uv_set) + "; Prism reads TEXCOORD_0/1, using 0");
        layer.uv_set = 0;
    }
    return layer;
}

void MaterialConverter::apply_specular_glossiness(const tinygltf::Value& extension, Material& material) {
    SpecularGlossiness factors;
    factors.diffuse = vec4_of(&extension, "diffuseFactor", glm::vec4(1.0f));
    factors.specular = vec3_of(&extension, "specularFactor", glm::vec3(1.0f));
    factors.glossiness = static_cast<float>(number(&extension, "glossinessFactor", 1.0));
    const TextureRef diffuse = texture_ref(&extension, "diffuseTexture");
    const TextureRef spec_gloss = texture_ref(&extension, "specularGlossinessTexture");
    std::optional<Texture> diffuse_texels = diffuse.index >= 0 ? decode(diffuse.index, true) : std::nullopt;
    std::optional<Texture> spec_gloss_texels = spec_gloss.index >= 0 ? decode(spec_gloss.index, true) : std::nullopt;
    material.textures.clear();
    material.metal_rough_map.reset();
    if (!diffuse_texels && !spec_gloss_texels) {
        const MetallicRoughness converted = metallic_roughness_of(factors);
        material.diffuse = glm::vec3(converted.base);
        material.alpha = converted.base.w;
        material.metallic = converted.metallic;
        material.roughness = converted.roughness;
        return;
    }
    // Both textures become one base-colour and one metallic-roughness texture, placed as the diffuse texture is
    // (or the specular-glossiness one without it); the factors are in the texels.
    auto [base, metal_rough] = metallic_roughness_textures(factors, diffuse_texels ? &*diffuse_texels : nullptr,
                                                           spec_gloss_texels ? &*spec_gloss_texels : nullptr,
                                                           file_ + ": material '" + material.name + "'");
    const TextureRef& place = diffuse_texels ? diffuse : spec_gloss;
    scene_.textures.push_back(std::move(base));
    material.textures.push_back(placed(static_cast<uint32_t>(scene_.textures.size() - 1), place.index, place.tex_coord,
                                       place.transform, material.name));
    scene_.textures.push_back(std::move(metal_rough));
    material.metal_rough_map = placed(static_cast<uint32_t>(scene_.textures.size() - 1), place.index, place.tex_coord,
                                      place.transform, material.name);
    material.diffuse = glm::vec3(1.0f);
    material.alpha = 1.0f;
    material.metallic = 1.0f;
    material.roughness = 1.0f;
}

Material MaterialConverter::convert(int index) {
    Material material;
    if (index < 0) {
        // Primitives without a material get Prism's light-grey default rather than glTF's white rough metal,
        // which a Whitted tracer would render as a mirror.
        return default_material();
    }
    const tinygltf::Material& source = model_.materials[index];
    const auto& pbr = source.pbrMetallicRoughness;
    material.name = source.name.empty() ? "material " + std::to_string(index) : source.name;

    glm::vec4 base{1.0f};
    for (size_t i = 0; i < 4 && i < pbr.baseColorFactor.size(); ++i)
        base[i] = static_cast<float>(pbr.baseColorFactor[i]);
    float metallic = std::clamp(static_cast<float>(pbr.metallicFactor), 0.0f, 1.0f);
    float roughness = std::clamp(static_cast<float>(pbr.roughnessFactor), 0.0f, 1.0f);
    material.diffuse = glm::vec3(base);
    material.use_vertex_colors = true;

    // A texture reference of the material (tinygltf's TextureInfo, NormalTextureInfo or OcclusionTextureInfo) as a
    // layer; colour textures are sRGB, data textures linear.
    auto layer_of = [&](const auto& info, bool srgb) {
        return layer(info.index, info.texCoord, extension(info.extensions, "KHR_texture_transform"), srgb,
                     material.name);
    };
    if (auto base_layer = layer_of(pbr.baseColorTexture, true)) material.textures.push_back(*base_layer);
    material.metal_rough_map = layer_of(pbr.metallicRoughnessTexture, false);
    material.emissive_map = layer_of(source.emissiveTexture, true);
    material.occlusion_map = layer_of(source.occlusionTexture, false);
    material.normal_map = layer_of(source.normalTexture, false);
    material.normal_scale = static_cast<float>(source.normalTexture.scale);
    material.metal_rough = true;
    material.metallic = metallic;
    material.roughness = roughness;
    material.occlusion_strength = std::clamp(static_cast<float>(source.occlusionTexture.strength), 0.0f, 1.0f);
    if (const tinygltf::Value* spec_gloss = extension(source.extensions, "KHR_materials_pbrSpecularGlossiness");
        spec_gloss && spec_gloss->IsObject()) {
        apply_specular_glossiness(*spec_gloss, material);
        base = glm::vec4(material.diffuse, material.alpha);
        metallic = material.metallic;
        roughness = material.roughness;
    }

    const tinygltf::Value* specular_ext = extension(source.extensions, "KHR_materials_specular");
    float specular_factor = static_cast<float>(number(specular_ext, "specularFactor", 1.0));
    auto extension_layer = [&](const tinygltf::Value* ext, const char* key,
                               bool color_data) -> std::optional<TextureLayer> {
        const TextureRef ref = texture_ref(ext, key);
        return layer(ref.index, ref.tex_coord, ref.transform, color_data, material.name);
    };
    material.specular_map = extension_layer(specular_ext, "specularTexture", false);
    material.specular_color_map = extension_layer(specular_ext, "specularColorTexture", true);
    if (const tinygltf::Value* film = extension(source.extensions, "KHR_materials_iridescence")) {
        material.iridescence = std::clamp(static_cast<float>(number(film, "iridescenceFactor", 0.0)), 0.0f, 1.0f);
        material.iridescence_ior = std::max(1.0f, static_cast<float>(number(film, "iridescenceIor", 1.3)));
        material.iridescence_thickness_min =
            std::max(0.0f, static_cast<float>(number(film, "iridescenceThicknessMinimum", 100.0)));
        material.iridescence_thickness_max =
            std::max(0.0f, static_cast<float>(number(film, "iridescenceThicknessMaximum", 400.0)));
        material.iridescence_map = extension_layer(film, "iridescenceTexture", false);
        material.iridescence_thickness_map = extension_layer(film, "iridescenceThicknessTexture", false);
    }
    // The coat's own normal map (clearcoatNormalTexture) is not read: the coat reflects about the base's normal.
    if (const tinygltf::Value* coat = extension(source.extensions, "KHR_materials_clearcoat")) {
        material.clearcoat = std::clamp(static_cast<float>(number(coat, "clearcoatFactor", 0.0)), 0.0f, 1.0f);
        material.clearcoat_roughness =
            std::clamp(static_cast<float>(number(coat, "clearcoatRoughnessFactor", 0.0)), 0.0f, 1.0f);
        material.clearcoat_map = extension_layer(coat, "clearcoatTexture", false);
        material.clearcoat_roughness_map = extension_layer(coat, "clearcoatRoughnessTexture", false);
    }
    glm::vec3 specular_color = vec3_of(specular_ext, "specularColorFactor", glm::vec3(1.0f));
    // Metals tint their reflection with the base colour, dielectrics with KHR_materials_specular's colour: the
    // kernel mixes the two per hit (kernels/material.h rt_surface_terms), as metallic may come from a texture.
    material.specular = specular_color;
    material.reflectivity = metallic * (1.0f - 0.5f * roughness);

    const tinygltf::Value* transmission_ext = extension(source.extensions, "KHR_materials_transmission");
    float transmission =
        std::clamp(static_cast<float>(number(transmission_ext, "transmissionFactor", 0.0)), 0.0f, 1.0f);
    float ior =
        std::max(1.0f, static_cast<float>(number(extension(source.extensions, "KHR_materials_ior"), "ior", 1.5)));
    // Alpha is per hit (base texture and vertex alpha too): the kernel's coverage, not a transmission.
    material.alpha = std::clamp(base.w, 0.0f, 1.0f);
    material.alpha_cutoff = static_cast<float>(source.alphaCutoff);
    if (source.alphaMode == "MASK") material.alpha_mode = AlphaMode::Mask;
    if (source.alphaMode == "BLEND") material.alpha_mode = AlphaMode::Blend;
    material.double_sided = source.doubleSided;

    if (transmission > 0.0f) {
        // A dielectric boundary: the seed's Fresnel term splits reflection and refraction, so the reflected part is
        // a full mirror (r = 1) and the refracted part carries the transmission.
        // The kernel takes 1 - metallic of it per hit (kernels/material.h): metallic may come from a texture, and the
        // factor alone (1 by default) would make a glass whose texture says "not metal" opaque.
        material.transmittance = transmission;
        material.reflectivity = 1.0f;
        set_specular_fresnel(material, ior, specular_factor);
        const tinygltf::Value* volume = extension(source.extensions, "KHR_materials_volume");
        glm::vec3 attenuation = vec3_of(volume, "attenuationColor", glm::vec3(1.0f));
        float distance = static_cast<float>(number(volume, "attenuationDistance", 0.0));
        float thickness = static_cast<float>(number(volume, "thicknessFactor", 0.0));
        material.ambient = glm::vec3(base);  // glTF tints transmitted light by the base colour
        if (thickness > 0.0f && distance > 0.0f && std::isfinite(distance)) {
            // Beer-Lambert: light keeps attenuationColor after attenuationDistance inside the medium, so
            // sigma = -ln(colour) / distance, applied by the kernel over the distance each ray travels inside.
            glm::vec3 clamped = glm::clamp(attenuation, glm::vec3(1e-6f), glm::vec3(1.0f));
            material.absorption = -glm::log(clamped) / distance;
        } else {
            // No distance (infinite) or a thin wall: the colour is a flat tint, as one crossing of the wall.
            material.ambient *= thickness > 0.0f ? glm::vec3(1.0f) : attenuation;
        }
        // glTF thickness 0 (or no volume) means thin-walled: the seed's thin shell. A volume means the mesh
        // encloses solid glass: the seed's solid refraction (thickness 0).
        material.thickness = thickness > 0.0f ? 0.0f : kThinWalledThickness;
        float dispersion =
            static_cast<float>(number(extension(source.extensions, "KHR_materials_dispersion"), "dispersion", 0.0));
        material.ior = dispersive_ior(ior, dispersion);
    } else {
        // Opaque: the kernel mixes metal and dielectric per hit (rt_surface_terms), Schlick from this F0.
        set_specular_fresnel(material, ior, specular_factor);
        material.ior = glm::vec3(ior);
    }

    float emissive_strength = static_cast<float>(
        number(extension(source.extensions, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0));
    material.emissive = first3(source.emissiveFactor, glm::vec3(0.0f)) * emissive_strength;
    if (extension(source.extensions, "KHR_materials_unlit")) make_unlit(material, base);
    return material;
}

}  // namespace prism::gltf
