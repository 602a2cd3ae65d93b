// validate_scene: the checks every backend relies on, run once after loading so a kernel never reads out of
// bounds or traces through NaNs. Messages name the scene source, the mesh (index and name) and the element.
// Degenerate (zero-area) triangles are allowed: real scans contain them and the BVH builder skips them.
#include <cmath>
#include <sstream>

#include "core/util/error.h"
#include "core/loaders/scene_loader.h"

namespace prism {
namespace {

template <int N>
bool finite(const glm::vec<N, float>& v) {
    for (int i = 0; i < N; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

// "material 3 'glass'" (the name only when there is one).
std::string labelled(const char* kind, size_t index, const std::string& name) {
    return std::string(kind) + " " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
}

template <int N>
std::string describe(const glm::vec<N, float>& v) {
    std::ostringstream out;
    out << "(";
    for (int i = 0; i < N; ++i) out << (i ? ", " : "") << v[i];
    out << ")";
    return out.str();
}

std::string describe(float v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

class Validator {
public:
    explicit Validator(const Scene& scene) : scene_(scene), source_(scene.source.empty() ? "scene" : scene.source) {}

    void run() {
        for (size_t m = 0; m < scene_.meshes.size(); ++m) check_mesh(m);
        for (size_t i = 0; i < scene_.materials.size(); ++i) check_material(i);
        for (size_t i = 0; i < scene_.textures.size(); ++i) check_texture(i);
        check_environment();
        for (size_t i = 0; i < scene_.instances.size(); ++i) check_instance(i);
        for (size_t i = 0; i < scene_.lights.size(); ++i) check_light(i);
        if (scene_.triangle_count() == 0) fail("scene has no triangles");
    }

private:
    [[noreturn]] void fail(const std::string& cause) const { throw file_error(source_, cause); }

    std::string mesh_name(size_t m) const { return labelled("mesh", m, scene_.meshes[m].name); }

    template <typename Attribute>
    void check_attribute(size_t m, const std::vector<Attribute>& values, const char* what) const {
        const Mesh& mesh = scene_.meshes[m];
        if (!values.empty() && values.size() != mesh.positions.size())
            fail(mesh_name(m) + ": " + std::to_string(values.size()) + " " + what + " for " +
                 std::to_string(mesh.positions.size()) + " vertices");
        for (size_t v = 0; v < values.size(); ++v)
            if (!finite(values[v]))
                fail(mesh_name(m) + ": vertex " + std::to_string(v) + " has a non-finite " + what + " " +
                     describe(values[v]));
    }

    void check_mesh(size_t m) const {
        const Mesh& mesh = scene_.meshes[m];
        check_attribute(m, mesh.positions, "position");
        check_attribute(m, mesh.normals, "normal");
        check_attribute(m, mesh.uv0, "TEXCOORD_0");
        check_attribute(m, mesh.uv1, "TEXCOORD_1");
        check_attribute(m, mesh.colors, "colour");
        const size_t vertex_count = mesh.positions.size();
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3& triangle = mesh.triangles[t];
            for (int corner = 0; corner < 3; ++corner)
                if (triangle[corner] >= vertex_count)
                    fail(mesh_name(m) + ": triangle " + std::to_string(t) + " references vertex " +
                         std::to_string(triangle[corner]) + " but there are " + std::to_string(vertex_count) +
                         " vertices");
        }
        if (mesh.triangle_materials.size() != mesh.triangles.size())
            fail(mesh_name(m) + ": " + std::to_string(mesh.triangle_materials.size()) + " triangle materials for " +
                 std::to_string(mesh.triangles.size()) + " triangles");
        for (size_t t = 0; t < mesh.triangle_materials.size(); ++t)
            if (mesh.triangle_materials[t] >= scene_.materials.size())
                fail(mesh_name(m) + ": triangle " + std::to_string(t) + " uses material " +
                     std::to_string(mesh.triangle_materials[t]) + " but there are " +
                     std::to_string(scene_.materials.size()) + " materials");
    }

    void check_material(size_t i) const {
        const Material& material = scene_.materials[i];
        const std::string name = labelled("material", i, material.name);
        for (size_t l = 0; l < material.textures.size(); ++l)
            check_layer(material.textures[l], name + ": texture layer " + std::to_string(l));
        const std::pair<const std::optional<TextureLayer>*, const char*> maps[] = {
            {&material.metal_rough_map, "metallic-roughness map"},
            {&material.emissive_map, "emissive map"},
            {&material.occlusion_map, "occlusion map"},
            {&material.normal_map, "normal map"},
            {&material.specular_map, "specular map"},
            {&material.specular_color_map, "specular colour map"},
            {&material.iridescence_map, "iridescence map"},
            {&material.iridescence_thickness_map, "iridescence thickness map"},
            {&material.clearcoat_map, "clearcoat map"},
            {&material.clearcoat_roughness_map, "clearcoat roughness map"}};
        for (const auto& [map, what] : maps)
            if (*map) check_layer(**map, name + ": " + what);
    }

    void check_layer(const TextureLayer& layer, const std::string& name) const {
        if (layer.texture >= scene_.textures.size())
            fail(name + " uses texture " + std::to_string(layer.texture) + " but there are " +
                 std::to_string(scene_.textures.size()) + " textures");
        if (layer.uv_set > 1) fail(name + " uses TEXCOORD_" + std::to_string(layer.uv_set) + " (only 0 and 1 exist)");
    }

    void check_texture(size_t i) const {
        const Texture& texture = scene_.textures[i];
        const std::string name = labelled("texture", i, texture.name);
        if (texture.width <= 0 || texture.height <= 0)
            fail(name + ": size " + std::to_string(texture.width) + "x" + std::to_string(texture.height));
        const size_t expected = static_cast<size_t>(texture.width) * static_cast<size_t>(texture.height);
        if (texture.texels.size() != expected)
            fail(name + ": " + std::to_string(texture.texels.size()) + " texels for " + std::to_string(texture.width) +
                 "x" + std::to_string(texture.height));
    }

    void check_environment() const {
        const Environment& environment = scene_.environment;
        const size_t needed = environment.kind == EnvironmentKind::CubeMap    ? 6
                              : environment.kind == EnvironmentKind::Equirect ? 1
                                                                              : 0;
        if (environment.textures.size() < needed)
            fail("environment needs " + std::to_string(needed) + " texture(s) but has " +
                 std::to_string(environment.textures.size()));
        for (size_t i = 0; i < environment.textures.size(); ++i)
            if (environment.textures[i] >= scene_.textures.size())
                fail("environment texture " + std::to_string(i) + " is texture " +
                     std::to_string(environment.textures[i]) + " but there are " +
                     std::to_string(scene_.textures.size()) + " textures");
    }

    void check_instance(size_t i) const {
        const Instance& instance = scene_.instances[i];
        const std::string name = labelled("instance", i, instance.name);
        if (instance.mesh >= scene_.meshes.size())
            fail(name + " uses mesh " + std::to_string(instance.mesh) + " but there are " +
                 std::to_string(scene_.meshes.size()) + " meshes");
        for (int column = 0; column < 4; ++column)
            if (!finite(instance.transform[column])) fail(name + " has a non-finite transform");
        if (instance.material_override != kNoMaterialOverride && instance.material_override >= scene_.materials.size())
            fail(name + " overrides its material with " + std::to_string(instance.material_override) +
                 " but there are " + std::to_string(scene_.materials.size()) + " materials");
    }

    // What the shade stage needs of a light: finite numbers, a direction where one is used, light that adds (a
    // negative one would darken), and a cone within glTF's bounds, 0 <= inner < outer <= pi / 2, loosened to what
    // exporters write: Blender gives a spot without blend equal angles, and pi / 2 is often rounded up to 1.5708.
    void check_light(size_t i) const {
        const Light& light = scene_.lights[i];
        const std::string name = "light " + std::to_string(i);
        if (light.type != LightType::Directional && !finite(light.position))
            fail(name + " has a non-finite position " + describe(light.position));
        if (light.type != LightType::Point &&
            (!finite(light.direction) || glm::dot(light.direction, light.direction) == 0.0f))
            fail(name + " has no usable direction " + describe(light.direction));
        const glm::vec3 emitted = light.color * light.intensity;
        if (!finite(emitted) || glm::any(glm::lessThan(emitted, glm::vec3(0.0f))))
            fail(name + ": colour x intensity " + describe(emitted) + " is not a finite, non-negative light");
        if (!std::isfinite(light.range) || light.range < 0.0f)
            fail(name + ": range " + describe(light.range) + " is not a finite distance >= 0");
        if (light.type == LightType::Spot &&
            !(light.inner_cone >= 0.0f && light.inner_cone <= light.outer_cone && light.outer_cone <= 1.5718f))
            fail(name + ": spot cone angles " + describe(light.inner_cone) + " and " + describe(light.outer_cone) +
                 " (radians) are not 0 <= inner <= outer <= pi/2");
    }

    const Scene& scene_;
    std::string source_;
};

}  // namespace

void validate_scene(const Scene& scene) { Validator(scene).run(); }

}  // namespace prism
