#include "core/gltf_material.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <tiny_gltf.h>

#include "core/error.h"
#include "core/image_io.h"
#include "core/seed_material.h"

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

glm::vec3 vec3_of(const tinygltf::Value* object, const char* key, glm::vec3 fallback) {
    if (!object || !object->IsObject() || !object->Has(key)) return fallback;
    const tinygltf::Value& value = object->Get(key);
    if (!value.IsArray() || value.ArrayLen() < 3) return fallback;
    glm::vec3 result;
    for (int i = 0; i < 3; ++i) {
        if (!value.Get(i).IsNumber()) return fallback;
        result[i] = static_cast<float>(value.Get(i).GetNumberAsDouble());
    }
    return result;
}

glm::vec2 vec2_of(const tinygltf::Value* object, const char* key, glm::vec2 fallback) {
    if (!object || !object->IsObject() || !object->Has(key)) return fallback;
    const tinygltf::Value& value = object->Get(key);
    if (!value.IsArray() || value.ArrayLen() < 2 || !value.Get(0).IsNumber() || !value.Get(1).IsNumber())
        return fallback;
    return {static_cast<float>(value.Get(0).GetNumberAsDouble()), static_cast<float>(value.Get(1).GetNumberAsDouble())};
}

glm::vec3 first3(const std::vector<double>& values, glm::vec3 fallback) {
    if (values.size() < 3) return fallback;
    return {static_cast<float>(values[0]), static_cast<float>(values[1]), static_cast<float>(values[2])};
}

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) (u, v, 1), the spec's matrix order; rows 0 and 1 of
// that 3x3 are what TextureLayer stores.
void apply_texture_transform(const tinygltf::Value* transform, TextureLayer& layer) {
    if (!transform) return;
    glm::vec2 offset = vec2_of(transform, "offset", {0.0f, 0.0f});
    glm::vec2 scale = vec2_of(transform, "scale", {1.0f, 1.0f});
    float rotation = static_cast<float>(number(transform, "rotation", 0.0));
    float c = std::cos(rotation), s = std::sin(rotation);
    layer.uv_row0 = {scale.x * c, -scale.y * s, offset.x};
    layer.uv_row1 = {scale.x * s, scale.y * c, offset.y};
    if (transform->IsObject() && transform->Has("texCoord") && transform->Get("texCoord").IsNumber())
        layer.uv_set = static_cast<uint32_t>(std::max(0, transform->Get("texCoord").GetNumberAsInt()));
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

bool MaterialConverter::color_texture(int index, uint32_t& scene_texture) {
    auto found = textures_.find(index);
    if (found != textures_.end()) {
        scene_texture = found->second;
        return true;
    }
    if (index < 0 || index >= static_cast<int>(model_.textures.size()))
        throw file_error(file_, "texture " + std::to_string(index) + " does not exist");
    int source = model_.textures[index].source;
    if (source < 0 || source >= static_cast<int>(model_.images.size())) {
        scene_.warnings.push_back(file_ + ": texture " + std::to_string(index) +
                                  " has no PNG/JPEG image Prism can decode; ignored");
        return false;
    }
    const tinygltf::Image& image = model_.images[source];
    if (image.image.empty()) {
        if (!image.uri.empty()) throw file_error(file_, "image '" + image.uri + "' not found or empty");
        throw file_error(file_, "image " + std::to_string(source) + " has no data");
    }
    std::string name = file_ + ": " + (image.uri.empty() ? "image " + std::to_string(source) : image.uri);
    scene_.textures.push_back(load_texture_from_memory(std::span<const uint8_t>(image.image), name, true));
    scene_texture = static_cast<uint32_t>(scene_.textures.size() - 1);
    textures_[index] = scene_texture;
    return true;
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
    for (size_t i = 0; i < 4 && i < pbr.baseColorFactor.size(); ++i) base[i] = static_cast<float>(pbr.baseColorFactor[i]);
    float metallic = std::clamp(static_cast<float>(pbr.metallicFactor), 0.0f, 1.0f);
    float roughness = std::clamp(static_cast<float>(pbr.roughnessFactor), 0.0f, 1.0f);
    material.diffuse = glm::vec3(base);
    material.use_vertex_colors = true;

    if (pbr.baseColorTexture.index >= 0) {
        TextureLayer layer;
        if (color_texture(pbr.baseColorTexture.index, layer.texture)) {
            layer.mode = TextureMode::Modulate;
            layer.uv_set = static_cast<uint32_t>(std::max(0, pbr.baseColorTexture.texCoord));
            apply_texture_transform(extension(pbr.baseColorTexture.extensions, "KHR_texture_transform"), layer);
            if (layer.uv_set > 1) {
                scene_.warnings.push_back(file_ + ": material '" + material.name + "' uses TEXCOORD_" +
                                          std::to_string(layer.uv_set) + "; Prism reads TEXCOORD_0/1, using 0");
                layer.uv_set = 0;
            }
            material.textures.push_back(layer);
        }
    }

    const tinygltf::Value* specular_ext = extension(source.extensions, "KHR_materials_specular");
    float specular_factor = static_cast<float>(number(specular_ext, "specularFactor", 1.0));
    glm::vec3 specular_color = vec3_of(specular_ext, "specularColorFactor", glm::vec3(1.0f));
    // Metals tint their reflection with the base colour; dielectrics with KHR_materials_specular's colour.
    material.specular = glm::mix(specular_color, glm::vec3(base), metallic);
    material.reflectivity = metallic * (1.0f - 0.5f * roughness);

    const tinygltf::Value* transmission_ext = extension(source.extensions, "KHR_materials_transmission");
    float transmission = std::clamp(static_cast<float>(number(transmission_ext, "transmissionFactor", 0.0)), 0.0f, 1.0f);
    float ior = std::max(1.0f, static_cast<float>(number(extension(source.extensions, "KHR_materials_ior"), "ior", 1.5)));
    bool blended = source.alphaMode == "BLEND" && base.w < 1.0f;
    if (blended && transmission == 0.0f) {
        transmission = 1.0f - base.w;   // see-through, not refracting
        ior = 1.0f;
    }

    if (transmission > 0.0f) {
        // A dielectric boundary: the seed's Fresnel term splits reflection and refraction, so the reflected part is
        // a full mirror (r = 1) and the refracted part carries the transmission.
        material.transmittance = transmission * (1.0f - metallic);
        material.reflectivity = 1.0f;
        set_dielectric_fresnel(material, std::min(1.0f, schlick_f0(ior) * specular_factor));
        const tinygltf::Value* volume = extension(source.extensions, "KHR_materials_volume");
        glm::vec3 attenuation = vec3_of(volume, "attenuationColor", glm::vec3(1.0f));
        material.ambient = attenuation * glm::vec3(base);   // glTF tints transmitted light by the base colour
        float thickness = static_cast<float>(number(volume, "thicknessFactor", 0.0));
        // glTF thickness 0 (or no volume) means thin-walled: the seed's thin shell. A volume means the mesh
        // encloses solid glass: the seed's solid refraction (thickness 0).
        material.thickness = thickness > 0.0f ? 0.0f : kThinWalledThickness;
        float dispersion = static_cast<float>(number(extension(source.extensions, "KHR_materials_dispersion"),
                                                     "dispersion", 0.0));
        material.ior = dispersive_ior(ior, dispersion);
    } else {
        set_opaque_fresnel(material);
        material.ior = glm::vec3(ior);
    }

    float emissive_strength =
        static_cast<float>(number(extension(source.extensions, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0));
    material.emissive = first3(source.emissiveFactor, glm::vec3(0.0f)) * emissive_strength;
    return material;
}

}  // namespace prism::gltf
