#include "core/loaders/gltf_morph.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "core/loaders/gltf_accessor.h"
#include "core/util/error.h"

namespace prism::gltf {

bool morph_changes(const tinygltf::Primitive& primitive, std::span<const double> weights) {
    const size_t targets = std::min(weights.size(), primitive.targets.size());
    return std::any_of(weights.begin(), weights.begin() + targets, [](double w) { return w != 0.0; });
}

void apply_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                         std::span<const double> weights, Mesh& mesh, const std::string& what,
                         const std::string& file) {
    const size_t targets = std::min(weights.size(), primitive.targets.size());
    bool moved_normals = false, moved_tangents = false;
    for (size_t t = 0; t < targets; ++t) {
        const float w = static_cast<float>(weights[t]);
        if (!std::isfinite(w))
            throw file_error(file, what + ": morph target " + std::to_string(t) + " has a weight that is not a number");
        if (w == 0.0f) continue;
        // One displacement attribute of target t, checked against the mesh's vertex count.
        auto displacements = [&](const char* name) {
            FloatArray array;
            auto found = primitive.targets[t].find(name);
            if (found == primitive.targets[t].end()) return array;
            array = read_floats(model, found->second, file);
            if (array.components != 3 || array.count != mesh.positions.size())
                throw file_error(file, what + ": morph target " + std::to_string(t) + " " + name +
                                           " must be VEC3 and as long as POSITION");
            return array;
        };
        if (FloatArray d = displacements("POSITION"); d.count)
            for (size_t v = 0; v < d.count; ++v) mesh.positions[v] += w * glm::vec3(d.at(v, 0), d.at(v, 1), d.at(v, 2));
        if (!mesh.normals.empty())
            if (FloatArray d = displacements("NORMAL"); d.count) {
                for (size_t v = 0; v < d.count; ++v)
                    mesh.normals[v] += w * glm::vec3(d.at(v, 0), d.at(v, 1), d.at(v, 2));
                moved_normals = true;
            }
        if (!mesh.tangents.empty())
            if (FloatArray d = displacements("TANGENT"); d.count) {
                for (size_t v = 0; v < d.count; ++v)
                    mesh.tangents[v] += glm::vec4(w * glm::vec3(d.at(v, 0), d.at(v, 1), d.at(v, 2)), 0.0f);
                moved_tangents = true;
            }
    }
    if (moved_normals)
        for (glm::vec3& n : mesh.normals)
            if (glm::dot(n, n) > 0.0f) n = glm::normalize(n);
    if (moved_tangents)
        for (glm::vec4& t : mesh.tangents)
            if (glm::vec3 xyz(t); glm::dot(xyz, xyz) > 0.0f) t = glm::vec4(glm::normalize(xyz), t.w);
}

}  // namespace prism::gltf
