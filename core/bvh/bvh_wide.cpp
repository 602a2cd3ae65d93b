// The wide layout (kernels/types.h BvhWideNode): the binary SAH tree collapsed into 8-ary nodes whose child boxes
// are stored per axis, so a traversal tests eight children with vector arithmetic (AVX or SSE on the cpu backend).
#include <algorithm>
#include <bit>
#include <limits>
#include <string>

#include "core/bvh/bvh.h"
#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism {

namespace {

uint32_t lower_w(const BvhNode& node) { return std::bit_cast<uint32_t>(node.lower.w); }
uint32_t upper_w(const BvhNode& node) { return std::bit_cast<uint32_t>(node.upper.w); }

// Lane k of a pair of 4-lane members (lanes 0-3 in the first, 4-7 in the second).
template <class Vector>
auto& lane(Vector& lanes_0_3, Vector& lanes_4_7, uint32_t k) {
    Vector& v = k < 4 ? lanes_0_3 : lanes_4_7;
    k &= 3;
    return k == 0 ? v.x : k == 1 ? v.y : k == 2 ? v.z : v.w;
}
#define PRISM_WIDE_LANE(node, member, k) lane((node).member##0, (node).member##1, (k))

class Collapser {
public:
    Collapser(const std::vector<BvhNode>& binary, uint32_t leaf_size)
        : binary_(binary), range_(binary.size()), leaf_size_(leaf_size) {
        // Each subtree's primitive range (its leaves are contiguous): children follow their parent.
        for (uint32_t index = uint32_t(binary.size()); index-- > 0;) {
            if (upper_w(binary[index]) != 0) {
                range_[index] = {lower_w(binary[index]), upper_w(binary[index])};
            } else if (binary.size() > 1) {
                const Range& left = range_[lower_w(binary[index])];
                const Range& right = range_[lower_w(binary[index]) + 1];
                range_[index] = {left.first, left.count + right.count};
            }
        }
    }

    std::vector<BvhWideNode> run() {
        wide_.push_back(empty_wide_node());
        // A root small enough for one leaf (or the empty tree's node, count 0, which needs no lane) takes lane 0.
        if (leaf(0)) {
            if (range_[0].count != 0) set_leaf_lane(wide_[0], 0, 0);
        } else {
            fill(0, 0);
        }
        return std::move(wide_);
    }

private:
    struct Range {
        uint32_t first = 0, count = 0;
    };

    // A subtree of at most leaf_size_ primitives becomes one leaf lane: testing its (at most two) blocks of four
    // triangles costs less than visiting a node that holds only its two leaves, the collapse's usual bottom level.
    bool leaf(uint32_t index) const { return upper_w(binary_[index]) != 0 || range_[index].count <= leaf_size_; }

    // Wide node `target` takes the children of binary node `source`, then opens the interior child with the
    // largest surface area (the likeliest to be entered) until it has RT_BVH_WIDTH children or only leaves.
    void fill(uint32_t target, uint32_t source) {
        uint32_t children[RT_BVH_WIDTH] = {lower_w(binary_[source]), lower_w(binary_[source]) + 1};
        uint32_t count = 2;
        while (count < RT_BVH_WIDTH) {
            int widest = -1;
            float widest_area = -1.0f;
            for (uint32_t k = 0; k < count; ++k) {
                if (leaf(children[k])) continue;
                float area = node_bounds(binary_[children[k]]).half_area();
                if (area > widest_area) widest = int(k), widest_area = area;
            }
            if (widest < 0) break;
            uint32_t opened = children[widest];
            children[widest] = lower_w(binary_[opened]);
            children[count++] = lower_w(binary_[opened]) + 1;
        }
        // Interior children get consecutive slots now and are filled after, so a parent precedes its children.
        uint32_t interior[RT_BVH_WIDTH];
        for (uint32_t k = 0; k < count; ++k) {
            if (leaf(children[k])) {
                set_leaf_lane(wide_[target], k, children[k]);
            } else {
                interior[k] = uint32_t(wide_.size());
                set_wide_lane_box(wide_[target], k, node_bounds(binary_[children[k]]));
                set_wide_lane_node(wide_[target], k, interior[k]);
                wide_.push_back(empty_wide_node());
            }
        }
        for (uint32_t k = 0; k < count; ++k)
            if (!leaf(children[k])) fill(interior[k], children[k]);
    }

    void set_leaf_lane(BvhWideNode& node, uint32_t k, uint32_t source) {
        set_wide_lane_box(node, k, node_bounds(binary_[source]));
        set_wide_lane_leaf(node, k, range_[source].first, range_[source].count);
    }

    const std::vector<BvhNode>& binary_;
    std::vector<Range> range_;
    uint32_t leaf_size_;
    std::vector<BvhWideNode> wide_;
};

}  // namespace

BvhWideNode empty_wide_node() {
    BvhWideNode node{};
    for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) set_wide_lane_box(node, k, Aabb{});
    return node;
}

// An empty box is +inf in all six: the wide slab test rejects it for every ray (kernels/intersect.h).
void set_wide_lane_box(BvhWideNode& node, uint32_t k, const Aabb& box) {
    const float inf = std::numeric_limits<float>::infinity();
    bool empty = box.empty();
    PRISM_WIDE_LANE(node, lower_x, k) = empty ? inf : box.lower.x;
    PRISM_WIDE_LANE(node, lower_y, k) = empty ? inf : box.lower.y;
    PRISM_WIDE_LANE(node, lower_z, k) = empty ? inf : box.lower.z;
    PRISM_WIDE_LANE(node, upper_x, k) = empty ? inf : box.upper.x;
    PRISM_WIDE_LANE(node, upper_y, k) = empty ? inf : box.upper.y;
    PRISM_WIDE_LANE(node, upper_z, k) = empty ? inf : box.upper.z;
}

Aabb wide_lane_bounds(const BvhWideNode& node, uint32_t k) {
    Aabb box;  // empty unless the lane holds a box
    if (PRISM_WIDE_LANE(node, lower_x, k) == std::numeric_limits<float>::infinity()) return box;
    box.lower = {PRISM_WIDE_LANE(node, lower_x, k), PRISM_WIDE_LANE(node, lower_y, k),
                 PRISM_WIDE_LANE(node, lower_z, k)};
    box.upper = {PRISM_WIDE_LANE(node, upper_x, k), PRISM_WIDE_LANE(node, upper_y, k),
                 PRISM_WIDE_LANE(node, upper_z, k)};
    return box;
}

uint32_t wide_lane_ref(const BvhWideNode& node, uint32_t k) { return PRISM_WIDE_LANE(node, child, k); }
bool wide_lane_used(const BvhWideNode& node, uint32_t k) { return wide_lane_ref(node, k) != 0; }
bool wide_lane_leaf(const BvhWideNode& node, uint32_t k) { return (wide_lane_ref(node, k) & RT_WIDE_LEAF) != 0; }
uint32_t wide_lane_first(const BvhWideNode& node, uint32_t k) { return (wide_lane_ref(node, k) & ~RT_WIDE_LEAF) >> 3; }
uint32_t wide_lane_count(const BvhWideNode& node, uint32_t k) { return (wide_lane_ref(node, k) & 7u) + 1; }

void set_wide_lane_node(BvhWideNode& node, uint32_t k, uint32_t index) {
    if (index == 0 || (index & RT_WIDE_LEAF) != 0) throw Error("internal: wide node index out of range");
    PRISM_WIDE_LANE(node, child, k) = index;
}

void set_wide_lane_leaf(BvhWideNode& node, uint32_t k, uint32_t first, uint32_t count) {
    if (count == 0 || count > RT_WIDE_LEAF_MAX)
        throw Error("internal: a wide BVH leaf holds 1 to " + std::to_string(RT_WIDE_LEAF_MAX) + " primitives, not " +
                    std::to_string(count));
    if (first >= RT_WIDE_FIRST_LIMIT)
        throw Error("scene: the wide BVH layout indexes fewer than " + std::to_string(RT_WIDE_FIRST_LIMIT) +
                    " triangles (use the stack layout)");
    PRISM_WIDE_LANE(node, child, k) = RT_WIDE_LEAF | first << 3 | (count - 1);
}

std::vector<BvhWideNode> collapse_bvh_wide(const std::vector<BvhNode>& stack_nodes, uint32_t leaf_size) {
    if (stack_nodes.empty()) throw Error("internal: collapsing an empty BVH");
    return Collapser(stack_nodes, std::min(leaf_size, RT_WIDE_LEAF_MAX)).run();
}

uint32_t wide_stack_bound(const std::vector<BvhWideNode>& wide, uint32_t root) {
    const BvhWideNode& node = wide.at(root);
    uint32_t used = 0, deepest = 0;
    for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
        if (!wide_lane_used(node, k)) continue;
        ++used;
        if (!wide_lane_leaf(node, k)) deepest = std::max(deepest, wide_stack_bound(wide, wide_lane_ref(node, k)));
    }
    return (used > 0 ? used - 1 : 0) + deepest;
}

void refit_bvh_wide(std::vector<BvhWideNode>& wide, const std::vector<uint32_t>& primitive_order,
                    std::span<const Aabb> primitive_bounds) {
    // Children follow their parent, so one reverse sweep sees every child node before its parent.
    for (uint32_t index = uint32_t(wide.size()); index-- > 0;) {
        BvhWideNode& node = wide[index];
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            if (!wide_lane_used(node, k)) continue;
            Aabb box;
            if (wide_lane_leaf(node, k)) {
                uint32_t first = wide_lane_first(node, k);
                for (uint32_t i = first; i < first + wide_lane_count(node, k); ++i) {
                    const Aabb& primitive = primitive_bounds[primitive_order[i]];
                    if (bvh_usable_bounds(primitive)) box.grow(primitive);
                }
            } else {
                const BvhWideNode& child = wide[wide_lane_ref(node, k)];
                for (uint32_t c = 0; c < RT_BVH_WIDTH; ++c) {
                    Aabb child_box = wide_lane_bounds(child, c);
                    if (!child_box.empty()) box.grow(child_box);
                }
            }
            set_wide_lane_box(node, k, box);
        }
    }
}

}  // namespace prism
