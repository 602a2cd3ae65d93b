// Triangle pre-splitting before a BVH build (Karras & Aila 2013, "Fast Parallel Construction of High-Quality
// Bounding Volume Hierarchies", section 5): a long or diagonal triangle's box is mostly empty space, and every ray
// through that space tests the triangle. Such triangles are cut along the planes of a dyadic grid over the scene
// (the planes the builder's top splits are most likely to use) into several references, each with the box of the
// part of the triangle on its side, before the SAH build sees them. The builder is unchanged; a triangle can then
// sit in more than one leaf.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/bvh/bvh.h"

namespace prism {

struct TriangleCorners {
    glm::vec3 a, b, c;
};

struct SplitReferences {
    std::vector<Aabb> bounds;         // what build_bvh gets: one box per reference
    std::vector<uint32_t> triangle;   // the input triangle each reference belongs to
};

// Adds about `budget` x (triangles with non-empty bounds) references, given to the triangles whose boxes waste the
// most area at the coarsest grid planes. `bounds[t]` empty leaves triangle t out (as build_bvh does). budget 0
// returns one reference per triangle, in order. Deterministic.
SplitReferences split_triangles(std::span<const TriangleCorners> corners, std::span<const Aabb> bounds,
                                float budget);

// A BVH built over split references indexes references in primitive_order: this maps them to triangles and drops a
// triangle's second reference within one leaf range (the stack layout's leaves; the wide layout's are handled
// where its blocks are written). Leaf counts shrink accordingly; leaf order is kept.
void map_split_references(Bvh& bvh, const SplitReferences& references);

}  // namespace prism
