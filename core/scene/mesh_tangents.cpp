#include "core/scene/mesh_tangents.h"

#include <algorithm>
#include <cmath>

namespace prism {
namespace {

glm::vec3 any_orthogonal(glm::vec3 n) {
    glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(axis, n));
}

float corner_angle(glm::vec3 corner, glm::vec3 a, glm::vec3 b) {
    glm::vec3 e1 = a - corner, e2 = b - corner;
    float l1 = glm::length(e1), l2 = glm::length(e2);
    if (l1 <= 0.0f || l2 <= 0.0f) return 0.0f;
    return std::acos(std::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0f, 1.0f));
}

}  // namespace

void generate_tangents(Mesh& mesh, uint32_t uv_set) {
    const std::vector<glm::vec2>& uv = uv_set == 1 ? mesh.uv1 : mesh.uv0;
    mesh.tangents.clear();
    if (uv.size() != mesh.positions.size()) return;
    size_t n = mesh.positions.size();
    std::vector<glm::vec3> tangent(n, glm::vec3(0.0f)), bitangent(n, glm::vec3(0.0f)), face_normal(n, glm::vec3(0.0f));
    for (const glm::uvec3& t : mesh.triangles) {
        const uint32_t index[3] = {t.x, t.y, t.z};
        glm::vec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
        glm::vec2 w[3] = {uv[t.x], uv[t.y], uv[t.z]};
        glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        glm::vec2 d1 = w[1] - w[0], d2 = w[2] - w[0];
        float det = d1.x * d2.y - d2.x * d1.y;
        if (det == 0.0f || !std::isfinite(det)) continue;
        // The object-space directions in which u and v grow on this triangle.
        glm::vec3 du = (e1 * d2.y - e2 * d1.y) / det;
        glm::vec3 dv = (e2 * d1.x - e1 * d2.x) / det;
        glm::vec3 normal = glm::cross(e1, e2);
        for (int k = 0; k < 3; ++k) {
            float weight = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            tangent[index[k]] += du * weight;
            bitangent[index[k]] += dv * weight;
            face_normal[index[k]] += normal;
        }
    }
    mesh.tangents.resize(n);
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 normal = mesh.normals.size() == n ? mesh.normals[i] : face_normal[i];
        normal = glm::dot(normal, normal) > 0.0f ? glm::normalize(normal) : glm::vec3(0, 0, 1);
        glm::vec3 t = tangent[i] - normal * glm::dot(normal, tangent[i]);
        t = glm::dot(t, t) > 1e-20f ? glm::normalize(t) : any_orthogonal(normal);
        float sign = glm::dot(glm::cross(normal, t), bitangent[i]) < 0.0f ? -1.0f : 1.0f;
        mesh.tangents[i] = glm::vec4(t, sign);
    }
}

}  // namespace prism
