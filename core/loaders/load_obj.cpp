// OBJ/MTL through tinyobjloader, mapped onto the seed's material model (docs/materials.md, "OBJ/MTL", has the mapping).
// tinyobjloader parses; this file finds MTL files and textures case-insensitively, fans polygons itself (so a
// face with a bad index is reported, not silently dropped), and merges OBJ's separate v/vt/vn index streams
// into one index per unique corner.
#include "core/loaders/load_obj.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/util/input_file.h"
#include "core/loaders/obj_text.h"
#include "core/loaders/obj_values.h"
#include "core/loaders/referenced_file.h"
#include "core/util/text_encoding.h"

namespace prism {
namespace {

std::string trim(std::string_view text) {
    const size_t begin = text.find_first_not_of(" \t\r");
    if (begin == std::string_view::npos) return {};
    const size_t end = text.find_last_not_of(" \t\r");
    return std::string(text.substr(begin, end - begin + 1));
}

// Where each material came from, and which of them name an IOR: tinyobjloader defaults Ni to 1 and cannot tell
// "Ni 1" from no Ni at all, which decides whether a mirror gets a Fresnel falloff.
struct MaterialOrigins {
    std::vector<std::filesystem::path> mtl_file;  // per tinyobj material index
    std::set<std::string> names_with_ior;
    std::set<std::string> names_with_dissolve;  // materials with a "d" statement
    std::vector<std::string> warnings;
};

// tinyobjloader's warnings, one per line, prefixed with the file they are about.
void add_warnings(const std::string& file, const std::string& text, std::vector<std::string>& warnings) {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        line = trim(line);
        // Every 3ds Max export writes both "d" and "Tr"; tinyobjloader's notice that "d" wins is not news.
        if (line.empty() || line.find("Both `d` and `Tr`") != std::string::npos) continue;
        // Some of its messages end in a line of punctuation alone ("Degenerated face found\n.").
        if (std::none_of(line.begin(), line.end(), [](unsigned char c) { return std::isalnum(c); })) continue;
        warnings.push_back(file + ": " + line);
    }
}

// tinyobjloader's own file reader wants exact names and one search folder; real MTL references are neither.
class CaseInsensitiveMaterialReader : public tinyobj::MaterialReader {
public:
    CaseInsensitiveMaterialReader(const std::filesystem::path& obj_file, MaterialOrigins& origins)
        : obj_file_(obj_file.string()), obj_directory_(obj_file.parent_path()), origins_(origins) {}

    bool operator()(const std::string& mtl_name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* name_to_index, std::string* warnings, std::string*) override {
        // Exceptions pass through tinyobjloader to load_obj's caller: a refused file is an error, not a warning.
        const std::filesystem::path path = find_referenced_file(obj_file_, trim(mtl_name), obj_directory_);
        if (path.empty()) {
            *warnings += "material library '" + shorten(mtl_name) + "' not found\n";
            return false;
        }
        std::stringstream text(utf8_text(read_input_file(path)));
        note_statements(text.str());
        std::string mtl_warnings;
        tinyobj::LoadMtl(name_to_index, materials, &text, &mtl_warnings, nullptr);
        add_warnings(path.string(), mtl_warnings, origins_.warnings);
        origins_.mtl_file.resize(materials->size(), path);
        return true;
    }

private:
    // Which materials state an IOR ("Ni") and a dissolve ("d"): tinyobjloader's defaults do not say.
    void note_statements(const std::string& text) {
        std::istringstream lines(text);
        std::string line, current;
        while (std::getline(lines, line)) {
            const std::string statement = trim(line);
            if (statement.rfind("newmtl", 0) == 0 && statement.size() > 6 && std::isspace(statement[6]))
                current = trim(std::string_view(statement).substr(7));
            else if (statement.rfind("Ni", 0) == 0 && statement.size() > 2 && std::isspace(statement[2]))
                origins_.names_with_ior.insert(current);
            else if (statement.rfind("d", 0) == 0 && statement.size() > 1 && std::isspace(statement[1]))
                origins_.names_with_dissolve.insert(current);
        }
    }

    std::string obj_file_;
    std::filesystem::path obj_directory_;
    MaterialOrigins& origins_;
};

glm::vec3 vec3_of(const tinyobj::real_t* values) { return glm::vec3(values[0], values[1], values[2]); }

float largest_component(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

Material convert_material(const tinyobj::material_t& source, bool has_ior, bool fully_transparent_means_opaque) {
    Material material;
    material.name = source.name;
    material.diffuse = vec3_of(source.diffuse);
    material.specular = vec3_of(source.specular);
    material.emissive = vec3_of(source.emission);
    // Mirror-like illumination models: 3 (ray-traced reflection), 5 (+ Fresnel), 7 (+ refraction).
    if (source.illum == 3 || source.illum == 5 || source.illum == 7)
        material.reflectivity = std::clamp(largest_component(material.specular), 0.0f, 1.0f);
    // tinyobjloader folds "Tr" into dissolve (d wins when both are given).
    float dissolve = std::clamp(static_cast<float>(source.dissolve), 0.0f, 1.0f);
    if (fully_transparent_means_opaque && dissolve == 0.0f) dissolve = 1.0f;
    if (dissolve < 1.0f) {
        material.transmittance = 1.0f - dissolve;
        const glm::vec3 filter = vec3_of(source.transmittance);
        // Tf 0 0 0 is also what an absent Tf reads as; a filter that blocks everything is never what was meant.
        material.ambient = largest_component(filter) > 0.0f ? filter : glm::vec3(1.0f);
    }
    if (has_ior) material.ior = glm::vec3(static_cast<float>(source.ior));
    const bool dielectric = material.transmittance > 0.0f || (material.reflectivity > 0.0f && has_ior);
    if (dielectric) {
        // Schlick's approximation with the material's own normal-incidence reflectance.
        const float ratio = (material.ior.x - 1.0f) / (material.ior.x + 1.0f);
        const float f0 = ratio * ratio;
        material.fresnel_bias = f0;
        material.fresnel_scale = 1.0f - f0;
    } else {
        material.fresnel_bias = 1.0f;  // R_f = 1: reflectivity alone decides, as in the seed's plain mirrors
        material.fresnel_scale = 0.0f;
    }
    material.fresnel_power = 5.0f;
    return material;
}

struct CornerKey {
    int position, normal, uv;
    bool operator==(const CornerKey&) const = default;
};
struct CornerHash {
    size_t operator()(const CornerKey& key) const {
        uint64_t h = static_cast<uint32_t>(key.position);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(key.normal);
        h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(key.uv);
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

}  // namespace

void load_obj(const std::filesystem::path& path, Scene& scene) {
    const std::string file = path.string();
    ObjText normalized = normalize_obj_text(file, utf8_text(read_input_file(path)));
    const std::string& text = normalized.text;
    scene.warnings.insert(scene.warnings.end(), normalized.warnings.begin(), normalized.warnings.end());
    check_obj_values(file, text);
    std::istringstream stream(text);

    tinyobj::attrib_t attributes;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> obj_materials;
    std::string warnings, errors;
    MaterialOrigins origins;
    CaseInsensitiveMaterialReader material_reader(path, origins);
    // Polygons are fanned below, not by tinyobjloader: it drops faces with bad indices with only a warning.
    const bool ok = tinyobj::LoadObj(&attributes, &shapes, &obj_materials, &warnings, &errors, &stream,
                                     &material_reader, /*triangulate=*/false, /*default_vcols_fallback=*/false);
    if (!ok) throw file_error(file, library_message(errors, "cannot parse OBJ file"));
    scene.warnings.insert(scene.warnings.end(), origins.warnings.begin(), origins.warnings.end());
    add_warnings(file, warnings + errors, scene.warnings);

    // Materials and their textures. Texture files shared between materials are loaded once.
    const uint32_t material_base = static_cast<uint32_t>(scene.materials.size());
    std::map<std::filesystem::path, uint32_t> texture_by_file;
    for (size_t i = 0; i < obj_materials.size(); ++i) {
        const tinyobj::material_t& source = obj_materials[i];
        // "Tr 1" without "d" is fully transparent by the MTL spec, but MeshLab and other exporters write it for
        // opaque surfaces (trimesh's fuze.obj: a textured bottle drawn as clear glass). A material nobody would see
        // is read as the opaque one meant, with a warning.
        const bool tr_means_opaque = source.dissolve <= 0.0 && origins.names_with_dissolve.count(source.name) == 0;
        if (tr_means_opaque)
            scene.warnings.push_back(file + ": material '" + source.name +
                                     "': 'Tr 1' (fully transparent) read as opaque, as MeshLab writes it");
        Material material = convert_material(source, origins.names_with_ior.count(source.name) > 0, tr_means_opaque);
        if (!source.diffuse_texname.empty()) {
            const std::filesystem::path mtl_file = i < origins.mtl_file.size() ? origins.mtl_file[i] : path;
            const std::filesystem::path texture_path =
                find_referenced_file(mtl_file.string(), trim(source.diffuse_texname), mtl_file.parent_path());
            if (texture_path.empty())
                throw file_error(mtl_file.string(), "material '" + source.name + "': texture '" +
                                                        shorten(source.diffuse_texname) + "' not found");
            auto [entry, inserted] =
                texture_by_file.try_emplace(texture_path, static_cast<uint32_t>(scene.textures.size()));
            if (inserted) scene.textures.push_back(load_texture(texture_path, /*color_data=*/true));
            TextureLayer layer;
            layer.texture = entry->second;
            layer.mode = TextureMode::Modulate;
            // map_Kd -s/-o scale and offset OBJ's (u, v); the mesh stores v flipped (1 - v), so the v row is
            // the same affine map conjugated by that flip: v' = s v + (1 - s - o).
            const tinyobj::texture_option_t& options = source.diffuse_texopt;
            layer.uv_row0 = glm::vec3(options.scale[0], 0.0f, options.origin_offset[0]);
            layer.uv_row1 = glm::vec3(0.0f, options.scale[1], 1.0f - options.scale[1] - options.origin_offset[1]);
            material.textures.push_back(layer);
        }
        scene.materials.push_back(std::move(material));
    }
    uint32_t default_material = UINT32_MAX;  // appended only when some face has no usemtl
    auto material_for = [&](int obj_index) -> uint32_t {
        if (obj_index >= 0 && static_cast<size_t>(obj_index) < obj_materials.size())
            return material_base + static_cast<uint32_t>(obj_index);
        if (default_material == UINT32_MAX) {
            default_material = static_cast<uint32_t>(scene.materials.size());
            Material fallback;
            fallback.name = "default";
            scene.materials.push_back(fallback);
        }
        return default_material;
    };

    // One mesh: de-index corners, fan polygons.
    const size_t position_count = attributes.vertices.size() / 3;
    const size_t normal_count = attributes.normals.size() / 3;
    const size_t uv_count = attributes.texcoords.size() / 2;
    const bool has_colors = attributes.colors.size() == attributes.vertices.size() && !attributes.colors.empty();
    Mesh mesh;
    mesh.name = path.stem().string();
    std::unordered_map<CornerKey, uint32_t, CornerHash> corner_index;
    bool any_normal = false, every_normal = true, any_uv = false;
    std::vector<CornerKey> corners;
    std::vector<uint32_t> polygon;
    size_t face_number = 0;
    for (const tinyobj::shape_t& shape : shapes) {
        size_t offset = 0;
        for (size_t face = 0; face < shape.mesh.num_face_vertices.size(); ++face, ++face_number) {
            const size_t count = shape.mesh.num_face_vertices[face];
            polygon.clear();
            for (size_t k = 0; k < count; ++k) {
                const tinyobj::index_t& index = shape.mesh.indices[offset + k];
                auto check = [&](int value, size_t limit, const char* what) {
                    if (value < 0 || static_cast<size_t>(value) >= limit)
                        throw file_error(file, "face " + std::to_string(face_number) + " references " + what + " " +
                                                   std::to_string(value + 1) + " but there are " +
                                                   std::to_string(limit));
                };
                check(index.vertex_index, position_count, "vertex");
                if (index.normal_index >= 0) check(index.normal_index, normal_count, "normal");
                if (index.texcoord_index >= 0) check(index.texcoord_index, uv_count, "texture coordinate");
                const CornerKey key{index.vertex_index, index.normal_index, index.texcoord_index};
                any_normal |= key.normal >= 0;
                every_normal &= key.normal >= 0;
                any_uv |= key.uv >= 0;
                auto [entry, inserted] = corner_index.try_emplace(key, static_cast<uint32_t>(corners.size()));
                if (inserted) corners.push_back(key);
                polygon.push_back(entry->second);
            }
            offset += count;
            if (count < 3) continue;  // points and lines carry no surface (tinyobjloader warns)
            const int material_id = face < shape.mesh.material_ids.size() ? shape.mesh.material_ids[face] : -1;
            const uint32_t material = material_for(material_id);
            for (size_t k = 1; k + 1 < count; ++k) {
                mesh.triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
                mesh.triangle_materials.push_back(material);
            }
        }
    }
    if (mesh.triangles.empty()) throw file_error(file, "no faces (not an OBJ file, or an empty one)");
    if (any_normal && !every_normal)
        scene.warnings.push_back(file + ": some faces have no normals; using flat normals for the whole mesh");
    const bool keep_normals = any_normal && every_normal;

    mesh.positions.reserve(corners.size());
    if (keep_normals) mesh.normals.reserve(corners.size());
    if (any_uv) mesh.uv0.reserve(corners.size());
    if (has_colors) mesh.colors.reserve(corners.size());
    for (const CornerKey& corner : corners) {
        mesh.positions.push_back(vec3_of(&attributes.vertices[3 * size_t(corner.position)]));
        if (keep_normals) mesh.normals.push_back(vec3_of(&attributes.normals[3 * size_t(corner.normal)]));
        if (any_uv) {
            // OBJ's v axis points up the image; textures are stored with row 0 at the top.
            mesh.uv0.push_back(corner.uv < 0 ? glm::vec2(0.0f)
                                             : glm::vec2(attributes.texcoords[2 * size_t(corner.uv)],
                                                         1.0f - attributes.texcoords[2 * size_t(corner.uv) + 1]));
        }
        if (has_colors) mesh.colors.emplace_back(vec3_of(&attributes.colors[3 * size_t(corner.position)]), 1.0f);
    }

    Instance instance;
    instance.mesh = static_cast<uint32_t>(scene.meshes.size());
    instance.name = mesh.name;
    scene.meshes.push_back(std::move(mesh));
    scene.instances.push_back(std::move(instance));
}

}  // namespace prism
