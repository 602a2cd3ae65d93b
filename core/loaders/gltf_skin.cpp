#include "core/loaders/gltf_skin.h"

#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>
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

std::vector<glm::mat4> joint_matrices(const tinygltf::Model& model, const Skin& skin,
                                      std::span<const glm::mat4> node_world, const std::string& file) {
    FloatArray inverse_bind;
    if (skin.inverse_bind_matrices >= 0) {
        inverse_bind = read_mat4s(model, skin.inverse_bind_matrices, file);
        if (inverse_bind.count < skin.joints.size())
            throw file_error(file, "accessor " + std::to_string(skin.inverse_bind_matrices) + ": " +
                                       std::to_string(inverse_bind.count) + " inverse bind matrices for " +
                                       std::to_string(skin.joints.size()) + " joints");
    }
    std::vector<glm::mat4> matrices(skin.joints.size());
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const size_t node = static_cast<size_t>(skin.joints[j]);
        if (node >= node_world.size())
            throw file_error(file, "joint " + std::to_string(node) + " is not a node (" +
                                       std::to_string(node_world.size()) + " nodes)");
        glm::mat4 inverse(1.0f);
        if (inverse_bind.count) inverse = glm::make_mat4(&inverse_bind.values[j * 16]);
        matrices[j] = node_world[node] * inverse;
    }
    return matrices;
}

void apply_skin(Mesh& mesh, std::span<const glm::mat4> joints, std::span<const Influences> influences,
                const std::string& what, const std::string& file) {
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        glm::mat4 blended(0.0f);
        float total = 0.0f;
        for (const Influences& set : influences)
            for (int k = 0; k < 4; ++k) {
                const float weight = set.weights.at(v, k);
                if (!(weight >= 0.0f) || !std::isfinite(weight))
                    throw file_error(file, what + ": vertex " + std::to_string(v) +
                                               " has a weight that is negative "
                                               "or not a number");
                if (weight == 0.0f) continue;
                const float joint = set.joints.at(v, k);
                if (!(joint >= 0.0f && joint < float(joints.size())))
                    throw file_error(file, what + ": vertex " + std::to_string(v) + " names joint " +
                                               std::to_string(joint) + ", but the skin has " +
                                               std::to_string(joints.size()));
                blended += joints[static_cast<size_t>(joint)] * weight;
                total += weight;
            }
        if (!(total > 0.0f)) continue;  // no influence: the vertex stays in the skin's space
        blended *= 1.0f / total;
        mesh.positions[v] = glm::vec3(blended * glm::vec4(mesh.positions[v], 1.0f));
        const glm::mat3 linear(blended);
        if (v < mesh.normals.size()) {
            // Normals by the inverse transpose (a skin may scale unevenly); a singular blend keeps the linear part.
            const bool invertible = std::abs(glm::determinant(linear)) > 1e-20f;
            glm::vec3 n = (invertible ? glm::inverseTranspose(linear) : linear) * mesh.normals[v];
            if (glm::dot(n, n) > 0.0f) mesh.normals[v] = glm::normalize(n);
        }
        if (v < mesh.tangents.size()) {
            glm::vec3 t = linear * glm::vec3(mesh.tangents[v]);
            if (glm::dot(t, t) > 0.0f) mesh.tangents[v] = glm::vec4(glm::normalize(t), mesh.tangents[v].w);
        }
    }
}

}  // namespace prism::gltf
