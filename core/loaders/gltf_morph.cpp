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

std::vector<float> morph_weights(const tinygltf::Primitive& primitive, std::span<const double> weights,
                                 const std::string& what, const std::string& file) {
    std::vector<float> out(primitive.targets.size(), 0.0f);
    for (size_t t = 0; t < out.size() && t < weights.size(); ++t) {
        out[t] = static_cast<float>(weights[t]);
        if (!std::isfinite(out[t]))
            throw file_error(file, what + ": morph target " + std::to_string(t) + " has a weight that is not a number");
    }
    return out;
}

MorphTarget read_morph_target(const tinygltf::Model& model, const tinygltf::Primitive& primitive, size_t t,
                              const Mesh& mesh, const std::string& what, const std::string& file) {
    // One displacement attribute of target t, checked against the mesh's vertex count.
    auto displacements = [&](const char* name) {
        std::vector<glm::vec3> out;
        auto found = primitive.targets[t].find(name);
        if (found == primitive.targets[t].end()) return out;
        const FloatArray array = read_floats(model, found->second, file);
        if (array.components != 3 || array.count != mesh.positions.size())
            throw file_error(file, what + ": morph target " + std::to_string(t) + " " + name +
                                       " must be VEC3 and as long as POSITION");
        out.resize(array.count);
        for (size_t v = 0; v < array.count; ++v) out[v] = {array.at(v, 0), array.at(v, 1), array.at(v, 2)};
        return out;
    };
    MorphTarget target;
    target.positions = displacements("POSITION");
    if (!mesh.normals.empty()) target.normals = displacements("NORMAL");
    if (!mesh.tangents.empty()) target.tangents = displacements("TANGENT");
    return target;
}

std::vector<MorphTarget> read_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                            const Mesh& mesh, const std::string& what, const std::string& file) {
    std::vector<MorphTarget> targets;
    targets.reserve(primitive.targets.size());
    for (size_t t = 0; t < primitive.targets.size(); ++t)
        targets.push_back(read_morph_target(model, primitive, t, mesh, what, file));
    return targets;
}

void apply_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                         std::span<const double> weights, Mesh& mesh, const std::string& what,
                         const std::string& file) {
    const std::vector<float> floats = morph_weights(primitive, weights, what, file);
    unsigned moved = 0;
    for (size_t t = 0; t < floats.size(); ++t) {
        if (floats[t] == 0.0f) continue;
        const MorphTarget target = read_morph_target(model, primitive, t, mesh, what, file);
        DeformedVertices vertices = take_deformed(mesh);
        moved |= add_morph_target(vertices, target, floats[t]);
        put_deformed(mesh, std::move(vertices));
    }
    DeformedVertices vertices = take_deformed(mesh);
    normalize_morphed(vertices, moved);
    put_deformed(mesh, std::move(vertices));
}

DeformedVertices take_deformed(Mesh& mesh) {
    return {std::move(mesh.positions), std::move(mesh.normals), std::move(mesh.tangents)};
}

void put_deformed(Mesh& mesh, DeformedVertices&& vertices) {
    mesh.positions = std::move(vertices.positions);
    mesh.normals = std::move(vertices.normals);
    mesh.tangents = std::move(vertices.tangents);
}

}  // namespace prism::gltf
