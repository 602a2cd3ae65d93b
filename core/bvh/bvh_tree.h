// The intermediate binary tree between the builders (bvh_build.cpp) and the flat layouts (bvh_flatten.cpp).
// Internal to core/: callers use build_bvh() from core/bvh/bvh.h.
#pragma once

#include <cstdint>
#include <deque>
#include <list>
#include <span>
#include <vector>

#include "core/bvh/bvh.h"

namespace prism {

struct BvhBuildNode {
    Aabb box;
    const BvhBuildNode* children[2] = {nullptr, nullptr};
    uint32_t first = 0;  // leaf: first position in BvhTree::primitive_order
    uint32_t count = 0;  // leaf: primitive count (0 only for the single leaf of an empty input)
    uint32_t nodes = 1;  // in the subtree rooted here, this one included: where flattening places each subtree
    bool leaf() const { return children[0] == nullptr; }
};

struct BvhTree {
    const BvhBuildNode* root = nullptr;
    std::vector<uint32_t> primitive_order;
    // Nodes live in one arena per build task; a deque keeps addresses stable while it grows.
    std::list<std::deque<BvhBuildNode>> arenas;
    uint32_t node_count = 0;
    uint32_t depth = 0;  // root alone: 1
};

// Bounds that can go into a tree: not empty on any axis and finite. Others (degenerate triangles) are left out.
bool bvh_usable_bounds(const Aabb& box);

BvhTree build_bvh_tree(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options,
                       const BvhProgress& progress = {});

// Large subtrees are written on up to `threads` threads (0: all); the array is the same for any count.
BvhNodes flatten_bvh_tree(const BvhTree& tree, BvhLayout layout, uint32_t threads = 1);

// The node box as written to a flat node: an empty box becomes lower = +FLT_MAX, upper = -FLT_MAX, which every
// slab test rejects without producing NaN (infinities would give inf - inf).
void set_node_box(BvhNode& node, const Aabb& box);

}  // namespace prism
