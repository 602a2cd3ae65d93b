// BVH construction and flattening (thesis 6.2, 6.4.1). One builder interface for both levels: a bottom-level BVH
// per mesh over its triangles, a top-level BVH over instance world bounds.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "kernels/types.h"

namespace prism {

struct Aabb {
    glm::vec3 lower{std::numeric_limits<float>::infinity()};
    glm::vec3 upper{-std::numeric_limits<float>::infinity()};
    void grow(const glm::vec3& p) { lower = glm::min(lower, p); upper = glm::max(upper, p); }
    void grow(const Aabb& b) { lower = glm::min(lower, b.lower); upper = glm::max(upper, b.upper); }
    bool empty() const { return lower.x > upper.x; }
    glm::vec3 center() const { return 0.5f * (lower + upper); }
    float half_area() const {
        glm::vec3 d = upper - lower;
        return empty() ? 0.0f : d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

enum class BvhMethod { BinnedSah, Median };   // Median: the seed's split (thesis Algorithm 6-1), to reproduce it
enum class BvhLayout : uint32_t { Stack = RT_BVH_LAYOUT_STACK, Escape = RT_BVH_LAYOUT_ESCAPE };

struct BvhBuildOptions {
    BvhMethod method = BvhMethod::BinnedSah;
    BvhLayout layout = BvhLayout::Stack;
    uint32_t max_leaf_size = 4;     // primitives per leaf (at most 255 in the escape layout)
    uint32_t bins = 16;             // SAH bins per axis
    uint32_t threads = 0;           // 0: std::thread::hardware_concurrency()
    float traversal_cost = 1.0f;    // SAH constants: cost of a node visit relative to one primitive test
    float intersection_cost = 1.0f;
};

struct Bvh {
    std::vector<BvhNode> nodes;              // node 0 is the root; see kernels/types.h for both layouts
    std::vector<uint32_t> primitive_order;   // leaf ranges index this; it maps to the caller's primitive indices
    BvhLayout layout = BvhLayout::Stack;
    float sah_cost = 0.0f;                   // expected cost of a random ray that hits the root box
    double build_ms = 0.0;
    BvhBuildOptions options;                 // as built (threads resolved); refit keeps sah_cost in its terms
    uint32_t primitive_count = 0;            // input primitives, left-out ones included (refit checks it)
    uint32_t depth = 0;                      // levels, root alone = 1; a stack traversal needs depth - 1 entries
};

// One flat node decoded, whatever the layout: what a traversal reads from the .w bits.
struct BvhNodeView {
    bool leaf = false;
    uint32_t first = 0;    // leaf: first position in primitive_order
    uint32_t count = 0;    // leaf: primitives
    uint32_t left = 0;     // interior: child indices
    uint32_t right = 0;
};
BvhNodeView decode_bvh_node(const Bvh& bvh, uint32_t index);

// Builds over primitives given by their bounds. Primitives with empty bounds (degenerate triangles) or non-finite
// ones are left out. An input with no usable primitive gives a single leaf with count 0 and the box
// lower = +FLT_MAX, upper = -FLT_MAX. In the stack layout that node reads as interior (count 0): a traversal must
// test the root box before descending. Throws prism::Error on invalid options (max_leaf_size 0, bins < 2) and on
// inputs the escape layout cannot index (2^24 primitives or more).
// Deterministic: the same input and options give the same nodes for any thread count.
Bvh build_bvh(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options);

// Recomputes every node box from new primitive bounds keeping the topology (dynamic rigid scenes: the top level
// is refit when instances move; rebuild when the quality drops). Primitives left out at build time stay out
// (rebuild if one becomes non-empty); one that becomes empty or non-finite contributes nothing. Updates sah_cost.
// Throws prism::Error when primitive_bounds is not as long as the input the BVH was built from.
void refit_bvh(Bvh& bvh, std::span<const Aabb> primitive_bounds);

// SAH cost of a flattened BVH (for `prism info` and the build benchmark).
float sah_cost(const Bvh& bvh, const BvhBuildOptions& options);

Aabb node_bounds(const BvhNode& node);

}  // namespace prism
