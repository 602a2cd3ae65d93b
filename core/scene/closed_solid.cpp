#include "core/scene/closed_solid.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace prism {
namespace {

// The bits of a coordinate, -0 taken as +0 (they are one position).
uint32_t position_bits(float f) { return std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f); }

// One id per distinct position: the first vertex there (an open-addressing table keyed by the position's bits).
std::vector<uint32_t> weld_positions(const std::vector<glm::vec3>& positions) {
    auto key = [&positions](uint32_t i) {
        const glm::vec3& p = positions[i];
        return std::array<uint32_t, 3>{position_bits(p.x), position_bits(p.y), position_bits(p.z)};
    };
    const size_t capacity = std::bit_ceil(positions.size() * 2 + 1);
    std::vector<uint32_t> table(capacity, UINT32_MAX);
    std::vector<uint32_t> id(positions.size());
    for (uint32_t i = 0; i < positions.size(); ++i) {
        std::array<uint32_t, 3> k = key(i);
        uint64_t h = (uint64_t(k[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(k[1]) * 0xC2B2AE3D27D4EB4Full) ^
                     (uint64_t(k[2]) * 0x165667B19E3779F9ull);
        size_t slot = size_t(h ^ (h >> 29)) & (capacity - 1);
        while (table[slot] != UINT32_MAX && key(table[slot]) != k) slot = (slot + 1) & (capacity - 1);
        if (table[slot] == UINT32_MAX) table[slot] = i;
        id[i] = table[slot];
    }
    return id;
}

// Whether each directed edge (u, v) of the triangles occurs once and its reverse (v, u) once: then every edge has
// exactly two triangles, wound opposite ways along it. Each vertex's outgoing edges are listed together (a counting
// sort).
bool edges_pair_up(const std::vector<glm::uvec3>& triangles, size_t vertex_count) {
    std::vector<uint32_t> start(vertex_count + 1, 0u);
    for (const glm::uvec3& t : triangles) {
        start[t.x + 1] += 1u;
        start[t.y + 1] += 1u;
        start[t.z + 1] += 1u;
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    std::vector<uint32_t> targets(start.back());
    for (const glm::uvec3& t : triangles) {
        targets[next[t.x]++] = t.y;
        targets[next[t.y]++] = t.z;
        targets[next[t.z]++] = t.x;
    }
    // A vertex has a handful of edges, which linear scans check fastest; the lists of a vertex with many (a fan,
    // or a hostile file's million triangles at one vertex) are sorted and searched instead.
    constexpr uint32_t kShortList = 16;
    auto list = [&](size_t u) { return std::span<uint32_t>(targets.data() + start[u], start[u + 1] - start[u]); };
    for (size_t u = 0; u < vertex_count; ++u) {
        std::span<uint32_t> out = list(u);
        if (out.size() <= kShortList) continue;
        std::sort(out.begin(), out.end());
        if (std::adjacent_find(out.begin(), out.end()) != out.end()) return false;  // an edge run one way twice
    }
    for (size_t u = 0; u < vertex_count; ++u) {
        std::span<uint32_t> out = list(u);
        for (size_t k = 0; k < out.size(); ++k) {
            uint32_t v = out[k];
            if (out.size() <= kShortList && std::find(out.begin() + k + 1, out.end(), v) != out.end())
                return false;  // an edge run one way twice
            std::span<uint32_t> back = list(v);
            bool reversed = back.size() <= kShortList ? std::find(back.begin(), back.end(), uint32_t(u)) != back.end()
                                                      : std::binary_search(back.begin(), back.end(), uint32_t(u));
            if (!reversed) return false;  // an edge with one triangle, or two wound the same way
        }
    }
    return true;
}

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// Whether every connected piece encloses a positive volume (the divergence theorem over its triangles) greater than
// a millionth of its bounding box's diagonal cubed: far above the rounding of the sum, so a flat sheet of
// triangle pairs, whose sum is rounding alone, is no solid. The sum is taken about a corner of the piece itself, so
// that its terms are of the piece's size however far from the origin it lies.
bool pieces_enclose_volume(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles) {
    std::vector<uint32_t> parent(positions.size());
    std::iota(parent.begin(), parent.end(), 0u);
    for (const glm::uvec3& t : triangles) {
        parent[find_root(parent, t.y)] = find_root(parent, t.x);
        parent[find_root(parent, t.z)] = find_root(parent, t.x);
    }
    for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = find_root(parent, v);  // each vertex's piece, once
    struct Piece {
        glm::dvec3 origin;
        double six_volume = 0.0;
        glm::dvec3 lower{INFINITY}, upper{-INFINITY};
    };
    std::vector<Piece> pieces;  // one per connected piece, numbered as first met
    std::vector<uint32_t> piece_of(positions.size(), UINT32_MAX);
    for (const glm::uvec3& t : triangles) {
        uint32_t& index = piece_of[parent[t.x]];
        if (index == UINT32_MAX) index = uint32_t(pieces.size()), pieces.push_back(Piece{glm::dvec3(positions[t.x])});
        Piece& piece = pieces[index];
        glm::dvec3 a = glm::dvec3(positions[t.x]) - piece.origin, b = glm::dvec3(positions[t.y]) - piece.origin,
                   c = glm::dvec3(positions[t.z]) - piece.origin;
        piece.six_volume += glm::dot(a, glm::cross(b, c));
        for (const glm::dvec3& p : {a, b, c}) {
            piece.lower = glm::min(piece.lower, p);
            piece.upper = glm::max(piece.upper, p);
        }
    }
    for (const Piece& piece : pieces) {
        double diagonal = glm::length(piece.upper - piece.lower);
        if (!(piece.six_volume / 6.0 > 1e-6 * diagonal * diagonal * diagonal)) return false;
    }
    return true;
}

}  // namespace

bool is_closed_solid(const Mesh& mesh) {
    const size_t n = mesh.positions.size();
    // The edge lists count in 32 bits: three entries a triangle.
    if (mesh.triangles.empty() || n >= (size_t(1) << 31) || mesh.triangles.size() >= (size_t(1) << 30)) return false;
    for (const glm::vec3& p : mesh.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
    for (const glm::uvec3& t : mesh.triangles)
        if (t.x >= n || t.y >= n || t.z >= n) return false;
    // Vertices at one position are one (glTF splits them at UV and normal seams; scans repeat some).
    std::vector<uint32_t> id = weld_positions(mesh.positions);
    std::vector<glm::uvec3> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) {
        glm::uvec3 w(id[t.x], id[t.y], id[t.z]);
        if (w.x != w.y && w.y != w.z && w.z != w.x) triangles.push_back(w);
    }
    if (triangles.empty() || !edges_pair_up(triangles, n)) return false;
    return pieces_enclose_volume(mesh.positions, triangles);
}

}  // namespace prism
