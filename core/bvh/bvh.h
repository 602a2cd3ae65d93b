// BVH construction and flattening (thesis 6.2, 6.4.1). One builder interface for both levels: a bottom-level BVH
// per mesh over its triangles, a top-level BVH over instance world bounds.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/util/uninitialized_vector.h"
#include "kernels/types.h"

namespace prism {

struct Aabb {
    glm::vec3 lower{std::numeric_limits<float>::infinity()};
    glm::vec3 upper{-std::numeric_limits<float>::infinity()};
    void grow(const glm::vec3& p) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    void grow(const Aabb& b) {
        lower = glm::min(lower, b.lower);
        upper = glm::max(upper, b.upper);
    }
    bool empty() const { return lower.x > upper.x; }
    glm::vec3 center() const { return 0.5f * (lower + upper); }
    float half_area() const {
        glm::vec3 d = upper - lower;
        return empty() ? 0.0f : d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

enum class BvhMethod { BinnedSah, Median };  // Median: the seed's split (thesis Algorithm 6-1), to reproduce it
// Wide: 4-ary nodes collapsed from the binary tree (kernels/types.h BvhWideNode); `nodes` keeps the binary tree in
// the stack layout (refit, SAH cost and node decoding work on it).
enum class BvhLayout : uint32_t {
    Stack = RT_BVH_LAYOUT_STACK,
    Escape = RT_BVH_LAYOUT_ESCAPE,
    Wide = RT_BVH_LAYOUT_WIDE
};

struct BvhBuildOptions {
    BvhMethod method = BvhMethod::BinnedSah;
    BvhLayout layout = BvhLayout::Stack;
    uint32_t max_leaf_size = 4;   // primitives per leaf (at most 255 in the escape layout)
    uint32_t bins = 16;           // SAH bins per axis
    uint32_t threads = 0;         // 0: std::thread::hardware_concurrency()
    float traversal_cost = 1.0f;  // SAH constants: cost of a node visit relative to one primitive test
    float intersection_cost = 1.0f;
    uint32_t wide_leaf_size = RT_WIDE_LEAF_MAX;  // the wide layout: subtrees of at most this many become one leaf
    // The wide layout: one world-space BVH over every instance's triangles instead of a top level over instances
    // (build_device_scene; core/render/device_scene_flat.cpp). For scenes whose instances do not move: it cannot be
    // refit.
    bool flatten_instances = false;
    // ... unless that stores more than this many times the meshes' own triangles (instancing-heavy scenes keep the
    // two-level layout; the built DeviceScene's bvh_options.flatten_instances says which one it got, false for
    // every layout but the wide one).
    float flatten_growth_limit = 2.0f;
    // build_device_scene: mark the instances whose mesh bounds a solid rays can enter (RT_INSTANCE_CLOSED_SOLID), so
    // that the shade stage traces no shadow ray the solid itself blocks. Off only to compare against.
    bool closed_solids = true;
};

// Where a build's time went (build_bvh's steps, wall clock): the benchmark reports them per thread count.
struct BvhBuildPhases {
    double tree_ms = 0.0;      // references and binned SAH splits (the binary tree)
    double flatten_ms = 0.0;   // the tree written as flat nodes in the layout's order
    double collapse_ms = 0.0;  // the wide layout only: binary nodes collapsed into 8-wide ones
    double sah_ms = 0.0;       // the SAH cost of the result
};

// Node arrays are sized first and then written whole by the builders' threads: they are not zeroed on one thread
// before (UninitializedVector).
using BvhNodes = UninitializedVector<BvhNode>;
using BvhWideNodes = UninitializedVector<BvhWideNode>;

struct Bvh {
    BvhNodes nodes;                         // node 0 is the root; see kernels/types.h for the layouts
    BvhWideNodes wide_nodes;                // the wide layout only: node 0 is the root
    std::vector<uint32_t> primitive_order;  // leaf ranges index this; it maps to the caller's primitive indices
    BvhLayout layout = BvhLayout::Stack;
    float sah_cost = 0.0f;  // expected cost of a random ray that hits the root box
    double build_ms = 0.0;
    BvhBuildPhases phases;         // build_ms by step
    BvhBuildOptions options;       // as built (threads resolved); refit keeps sah_cost in its terms
    uint32_t primitive_count = 0;  // input primitives, left-out ones included (refit checks it)
    uint32_t depth = 0;            // levels, root alone = 1; a stack traversal needs depth - 1 entries
};

// One flat node decoded, whatever the layout: what a traversal reads from the .w bits.
struct BvhNodeView {
    bool leaf = false;
    uint32_t first = 0;  // leaf: first position in primitive_order
    uint32_t count = 0;  // leaf: primitives
    uint32_t left = 0;   // interior: child indices
    uint32_t right = 0;
};
BvhNodeView decode_bvh_node(const Bvh& bvh, uint32_t index);

// Builds over primitives given by their bounds. Primitives with empty bounds (degenerate triangles) or non-finite
// ones are left out. An input with no usable primitive gives a single leaf with count 0 and the box
// lower = +FLT_MAX, upper = -FLT_MAX. In the stack layout that node reads as interior (count 0): a traversal must
// test the root box before descending. Throws prism::Error on invalid options (max_leaf_size 0, bins < 2) and on
// inputs the escape layout cannot index (2^24 primitives or more).
// Deterministic: the same input and options give the same nodes for any thread count.
// `progress` (optional) hears the fraction of primitives placed in leaves so far, at most once per percent, from
// any of the build's threads (prism render shows it with an ETA: apps/progress.h).
using BvhProgress = std::function<void(double fraction)>;
Bvh build_bvh(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options, const BvhProgress& progress = {});

// Recomputes every node box (wide nodes too) from new primitive bounds keeping the topology (dynamic rigid scenes: the
// top level is refit when instances move; rebuild when the quality drops). Primitives left out at build time stay out
// (rebuild if one becomes non-empty); one that becomes empty or non-finite contributes nothing. Updates sah_cost.
// Throws prism::Error when primitive_bounds is not as long as the input the BVH was built from.
void refit_bvh(Bvh& bvh, std::span<const Aabb> primitive_bounds);

// SAH cost of a flattened BVH (for `prism info` and the build benchmark).
float sah_cost(const Bvh& bvh, const BvhBuildOptions& options);

Aabb node_bounds(const BvhNode& node);

// ---- The wide layout (core/bvh/bvh_wide.cpp) ----
// Collapses a binary BVH in the stack layout: each wide node takes a binary node's two children and opens the
// interior child with the largest surface area until it has RT_BVH_WIDTH (8) children (or only leaves). A subtree
// of at most leaf_size primitives (capped at RT_WIDE_LEAF_MAX) is one leaf. A parent precedes its children; unused
// lanes hold the empty box and child 0. A root that is a leaf becomes one wide node with it in lane 0 (the empty
// tree: no lane used). Binary leaves must hold at most RT_WIDE_LEAF_MAX primitives.
// The same nodes for any `threads` (counted first, then the subtrees below the top nodes written in place at once).
BvhWideNodes collapse_bvh_wide(const BvhNodes& stack_nodes, uint32_t leaf_size = RT_WIDE_LEAF_MAX,
                               uint32_t threads = 1);
// Refits the boxes of collapsed nodes in place (leaf ranges index primitive_order, as in the binary tree).
void refit_bvh_wide(BvhWideNodes& wide, const std::vector<uint32_t>& primitive_order,
                    std::span<const Aabb> primitive_bounds);
// The most entries a wide traversal (kernels/traverse.h) can hold on its stack below `root`: each node on a path
// leaves at most (its children - 1) behind.
uint32_t wide_stack_bound(const BvhWideNodes& wide, uint32_t root);

// One lane (child) of a wide node.
BvhWideNode empty_wide_node();
void set_wide_lane_box(BvhWideNode& node, uint32_t lane, const Aabb& box);
Aabb wide_lane_bounds(const BvhWideNode& node, uint32_t lane);
uint32_t wide_lane_ref(const BvhWideNode& node, uint32_t lane);  // as stored: node index or leaf reference
bool wide_lane_used(const BvhWideNode& node, uint32_t lane);
bool wide_lane_leaf(const BvhWideNode& node, uint32_t lane);
uint32_t wide_lane_first(const BvhWideNode& node, uint32_t lane);  // a leaf's first primitive
uint32_t wide_lane_count(const BvhWideNode& node, uint32_t lane);  // a leaf's primitive count
void set_wide_lane_node(BvhWideNode& node, uint32_t lane, uint32_t index);
// Throws prism::Error for a count outside 1..RT_WIDE_LEAF_MAX or first at or above RT_WIDE_FIRST_LIMIT.
void set_wide_lane_leaf(BvhWideNode& node, uint32_t lane, uint32_t first, uint32_t count);

}  // namespace prism
