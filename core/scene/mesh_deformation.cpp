#include "core/scene/mesh_deformation.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>

namespace prism {

unsigned add_morph_target(DeformedVertices& vertices, const MorphTarget& target, float weight) {
    if (weight == 0.0f) return 0;
    unsigned moved = 0;
    for (size_t v = 0; v < target.positions.size() && v < vertices.positions.size(); ++v)
        vertices.positions[v] += weight * target.positions[v];
    if (!vertices.normals.empty() && !target.normals.empty()) {
        for (size_t v = 0; v < target.normals.size() && v < vertices.normals.size(); ++v)
            vertices.normals[v] += weight * target.normals[v];
        moved |= 1u;
    }
    if (!vertices.tangents.empty() && !target.tangents.empty()) {
        for (size_t v = 0; v < target.tangents.size() && v < vertices.tangents.size(); ++v)
            vertices.tangents[v] += glm::vec4(weight * target.tangents[v], 0.0f);
        moved |= 2u;
    }
    return moved;
}

void normalize_morphed(DeformedVertices& vertices, unsigned moved) {
    if (moved & 1u)
        for (glm::vec3& n : vertices.normals)
            if (glm::dot(n, n) > 0.0f) n = glm::normalize(n);
    if (moved & 2u)
        for (glm::vec4& t : vertices.tangents)
            if (glm::vec3 xyz(t); glm::dot(xyz, xyz) > 0.0f) t = glm::vec4(glm::normalize(xyz), t.w);
}

void morph_vertices(DeformedVertices& vertices, std::span<const MorphTarget> targets, std::span<const float> weights) {
    unsigned moved = 0;
    for (size_t t = 0; t < targets.size() && t < weights.size(); ++t)
        moved |= add_morph_target(vertices, targets[t], weights[t]);
    normalize_morphed(vertices, moved);
}

void skin_vertices(DeformedVertices& vertices, const SkinInfluences& influences,
                   std::span<const glm::mat4> joint_matrices) {
    const size_t n = influences.per_vertex;
    for (size_t v = 0; v < vertices.positions.size() && (v + 1) * n <= influences.weights.size(); ++v) {
        glm::mat4 blended(0.0f);
        float total = 0.0f;
        for (size_t k = v * n; k < (v + 1) * n; ++k) {
            const float weight = influences.weights[k];
            if (weight == 0.0f || influences.joints[k] >= joint_matrices.size()) continue;
            blended += joint_matrices[influences.joints[k]] * weight;
            total += weight;
        }
        if (!(total > 0.0f)) continue;  // no influence: the vertex stays in the skin's space
        blended *= 1.0f / total;
        vertices.positions[v] = glm::vec3(blended * glm::vec4(vertices.positions[v], 1.0f));
        const glm::mat3 linear(blended);
        if (v < vertices.normals.size()) {
            const bool invertible = std::abs(glm::determinant(linear)) > 1e-20f;
            glm::vec3 normal = (invertible ? glm::inverseTranspose(linear) : linear) * vertices.normals[v];
            if (glm::dot(normal, normal) > 0.0f) vertices.normals[v] = glm::normalize(normal);
        }
        if (v < vertices.tangents.size()) {
            glm::vec3 tangent = linear * glm::vec3(vertices.tangents[v]);
            if (glm::dot(tangent, tangent) > 0.0f)
                vertices.tangents[v] = glm::vec4(glm::normalize(tangent), vertices.tangents[v].w);
        }
    }
}

}  // namespace prism
