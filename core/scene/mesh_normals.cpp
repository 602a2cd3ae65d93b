#include "core/scene/mesh_normals.h"

#include <cmath>

namespace prism {

void compute_smooth_normals(Mesh& mesh) {
    std::vector<glm::vec3> sums(mesh.positions.size(), glm::vec3(0.0f));
    for (const glm::uvec3& t : mesh.triangles) {
        if (t.x >= sums.size() || t.y >= sums.size() || t.z >= sums.size()) continue;  // validate_scene reports it
        glm::vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
        glm::vec3 n = glm::cross(b - a, c - a);  // length = twice the area: the weight
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) continue;
        sums[t.x] += n;
        sums[t.y] += n;
        sums[t.z] += n;
    }
    mesh.normals.resize(sums.size());
    for (size_t i = 0; i < sums.size(); ++i) {
        float length = glm::length(sums[i]);
        mesh.normals[i] = length > 0.0f && std::isfinite(length) ? sums[i] / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace prism
