#include "core/loaders/gltf_skin.h"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "core/util/error.h"

namespace prism::gltf {

std::vector<Skin> parse_skins(const nlohmann::json& skins, const std::string& file) {
    std::vector<Skin> out;
    if (skins.is_null()) return out;
    if (!skins.is_array()) throw file_error(file, "\"skins\" is not an array");
    for (size_t i = 0; i < skins.size(); ++i) {
        const nlohmann::json& entry = skins[i];
        const std::string what = "skin " + std::to_string(i);
        if (!entry.is_object()) throw file_error(file, what + " is not an object");
        Skin skin;
        auto joints = entry.find("joints");
        if (joints == entry.end() || !joints->is_array() || joints->empty())
            throw file_error(file, what + ": \"joints\" must be a non-empty array of node indices");
        for (const nlohmann::json& joint : *joints) {
            if (!joint.is_number_integer() || joint.get<int64_t>() < 0 || joint.get<int64_t>() > INT32_MAX)
                throw file_error(file, what + ": a joint is not a node index");
            skin.joints.push_back(static_cast<int>(joint.get<int64_t>()));
        }
        if (auto ibm = entry.find("inverseBindMatrices"); ibm != entry.end()) {
            if (!ibm->is_number_integer() || ibm->get<int64_t>() < 0 || ibm->get<int64_t>() > INT32_MAX)
                throw file_error(file, what + ": \"inverseBindMatrices\" is not an accessor index");
            skin.inverse_bind_matrices = static_cast<int>(ibm->get<int64_t>());
        }
        out.push_back(std::move(skin));
    }
    return out;
}

std::vector<glm::mat4> inverse_bind_matrices(const tinygltf::Model& model, const Skin& skin, const std::string& file) {
    std::vector<glm::mat4> matrices(skin.joints.size(), glm::mat4(1.0f));
    if (skin.inverse_bind_matrices < 0) return matrices;
    const FloatArray inverse_bind = read_mat4s(model, skin.inverse_bind_matrices, file);
    if (inverse_bind.count < skin.joints.size())
        throw file_error(file, "accessor " + std::to_string(skin.inverse_bind_matrices) + ": " +
                                   std::to_string(inverse_bind.count) + " inverse bind matrices for " +
                                   std::to_string(skin.joints.size()) + " joints");
    for (size_t j = 0; j < matrices.size(); ++j) matrices[j] = glm::make_mat4(&inverse_bind.values[j * 16]);
    return matrices;
}

std::vector<glm::mat4> joint_matrices(const tinygltf::Model& model, const Skin& skin,
                                      std::span<const glm::mat4> node_world, const std::string& file) {
    std::vector<glm::mat4> matrices = inverse_bind_matrices(model, skin, file);
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const size_t node = static_cast<size_t>(skin.joints[j]);
        if (node >= node_world.size())
            throw file_error(file, "joint " + std::to_string(node) + " is not a node (" +
                                       std::to_string(node_world.size()) + " nodes)");
        matrices[j] = node_world[node] * matrices[j];
    }
    return matrices;
}

SkinInfluences skin_influences(std::span<const Influences> sets, size_t vertex_count, size_t joint_count,
                               const std::string& what, const std::string& file) {
    SkinInfluences out;
    out.per_vertex = uint32_t(4 * sets.size());
    out.joints.resize(vertex_count * out.per_vertex);
    out.weights.resize(vertex_count * out.per_vertex);
    size_t next = 0;
    for (size_t v = 0; v < vertex_count; ++v)
        for (const Influences& set : sets)
            for (int k = 0; k < 4; ++k, ++next) {
                const float weight = set.weights.at(v, k);
                if (!(weight >= 0.0f) || !std::isfinite(weight))
                    throw file_error(file, what + ": vertex " + std::to_string(v) +
                                               " has a weight that is negative or not a number");
                const float joint = set.joints.at(v, k);
                if (weight != 0.0f && !(joint >= 0.0f && joint < float(joint_count)))
                    throw file_error(file, what + ": vertex " + std::to_string(v) + " names joint " +
                                               std::to_string(joint) + ", but the skin has " +
                                               std::to_string(joint_count));
                out.joints[next] = weight != 0.0f ? static_cast<uint32_t>(joint) : 0u;
                out.weights[next] = weight;
            }
    return out;
}

}  // namespace prism::gltf
