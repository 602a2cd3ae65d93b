#include "core/scene/corner_uvs.h"

#include <bit>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/util/error.h"

namespace prism {
namespace {

// A (vertex, coordinate) pair as one hashable key, the coordinate by its bits: equal bits share a vertex (-0 and
// +0 split one needlessly, which costs a vertex, never a wrong coordinate).
struct Corner {
    uint32_t vertex;
    uint32_t u, v;
    bool operator==(const Corner&) const = default;
};
struct CornerHash {
    size_t operator()(const Corner& c) const {
        uint64_t h = c.vertex;
        h = h * 0x9E3779B97F4A7C15ull ^ c.u;
        h = h * 0x9E3779B97F4A7C15ull ^ c.v;
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

}  // namespace

void apply_corner_uvs(Mesh& mesh, std::span<const glm::vec2> corner_uvs) {
    if (corner_uvs.size() != mesh.triangles.size() * 3) throw Error("internal: corner coordinates per triangle");
    const bool normals = !mesh.normals.empty(), colors = !mesh.colors.empty();
    Mesh split;
    split.positions.reserve(mesh.positions.size());
    std::unordered_map<Corner, uint32_t, CornerHash> index_of;
    index_of.reserve(mesh.positions.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        glm::uvec3& triangle = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            const uint32_t vertex = triangle[k];
            const glm::vec2 uv = corner_uvs[3 * t + size_t(k)];
            const Corner key{vertex, std::bit_cast<uint32_t>(uv.x), std::bit_cast<uint32_t>(uv.y)};
            auto [entry, inserted] = index_of.try_emplace(key, uint32_t(split.positions.size()));
            if (inserted) {
                split.positions.push_back(mesh.positions[vertex]);
                if (normals) split.normals.push_back(mesh.normals[vertex]);
                if (colors) split.colors.push_back(mesh.colors[vertex]);
                split.uv0.push_back(uv);
            }
            triangle[k] = entry->second;
        }
    }
    mesh.positions = std::move(split.positions);
    mesh.normals = std::move(split.normals);
    mesh.colors = std::move(split.colors);
    mesh.uv0 = std::move(split.uv0);
    mesh.uv1.clear();
    mesh.tangents.clear();
}

}  // namespace prism
