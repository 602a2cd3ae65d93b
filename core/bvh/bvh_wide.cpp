// The wide layout (kernels/types.h BvhWideNode): the binary SAH tree collapsed into 8-ary nodes whose child boxes
// are stored per axis, so a traversal tests eight children with vector arithmetic (AVX or SSE on the cpu backend).
#include <algorithm>
#include <bit>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include "core/bvh/bvh.h"
#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"
#include "core/util/parallel_indices.h"

namespace prism {

namespace {

// Subtrees of fewer primitives collapse on one thread (starting threads would cost more than it saves).
constexpr uint32_t kParallelCollapseFrom = 1u << 16;
constexpr size_t kParallelMeasureFrom = 1u << 16;  // binary nodes

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
    // The per-node tables are left uninitialized (zeroing them would be a serial pass over every node): the walk
    // below writes each node's entries, every node being reachable from the root.
    Collapser(const BvhNodes& binary, uint32_t leaf_size, uint32_t threads)
        : binary_(binary),
          range_(new Range[binary.size()]),
          area_(new float[binary.size()]),
          count_(new uint32_t[binary.size()]),
          leaf_size_(leaf_size) {
        if (binary.size() == 1 && upper_w(binary[0]) == 0) {
            range_[0] = {0, 0};  // the empty tree's one node (a leaf of count 0)
            area_[0] = node_bounds(binary[0]).half_area();
        } else {
            // A small tree (most meshes of a many-mesh scene) is measured faster than threads would start.
            measure(0, binary.size() >= kParallelMeasureFrom ? threads : 1u);
        }
    }

    BvhWideNodes run(uint32_t threads) {
        BvhWideNodes wide;
        // A root small enough for one leaf (or the empty tree's node, count 0, which needs no lane) takes lane 0.
        if (leaf(0)) {
            wide.push_back(empty_);
            if (range_[0].count != 0) set_leaf_lane(wide[0], 0, 0);
        } else if (threads <= 1 || range_[0].count < kParallelCollapseFrom) {
            // Each wide node opens at least one binary interior node, and a subtree of n primitives has fewer than
            // 2n binary nodes: reserved so growing never copies (pages never written are never touched).
            wide.reserve(range_[0].count + 1);
            wide.resize(1);
            uint32_t next = 1;
            fill(wide, 0, 0, next);
        } else {
            // Counted first, so the array is sized once and every part of it written in place, on several threads.
            wide.resize(count_below(0, threads));
            place(wide, 0, 0, 1, threads);
        }
        return wide;
    }

private:
    struct Range {
        uint32_t first, count;
    };

    // Each subtree's primitive range (its leaves are contiguous) and each node's half area, children before their
    // parent; the top subtrees on threads of their own (as bvh_flatten.cpp splits them).
    Range measure(uint32_t index, uint32_t threads) {
        area_[index] = node_bounds(binary_[index]).half_area();
        if (upper_w(binary_[index]) != 0) return range_[index] = {lower_w(binary_[index]), upper_w(binary_[index])};
        const uint32_t left = lower_w(binary_[index]);
        Range left_range, right_range;
        if (threads > 1) {
            std::thread worker([&] { left_range = measure(left, threads / 2); });
            right_range = measure(left + 1, threads - threads / 2);
            worker.join();
        } else {
            left_range = measure(left, 1);
            right_range = measure(left + 1, 1);
        }
        return range_[index] = {left_range.first, left_range.count + right_range.count};
    }

    // A subtree of at most leaf_size_ primitives becomes one leaf lane: testing its (at most two) blocks of four
    // triangles costs less than visiting a node that holds only its two leaves, the collapse's usual bottom level.
    bool leaf(uint32_t index) const { return upper_w(binary_[index]) != 0 || range_[index].count <= leaf_size_; }

    // count_[source]: how many wide nodes the subtree under binary interior node `source` collapses into (itself
    // and every wide node below it), and the same for each interior child it opens, recursively. With threads to
    // spare, the children are counted at the same time, each with its share of the threads (by primitives).
    uint32_t count_below(uint32_t source, uint32_t threads) {
        uint32_t children[RT_BVH_WIDTH];
        uint32_t count = open_children(source, children);
        uint32_t interior[RT_BVH_WIDTH], interior_count = 0;
        for (uint32_t k = 0; k < count; ++k)
            if (!leaf(children[k])) interior[interior_count++] = children[k];
        if (threads <= 1 || range_[source].count < kParallelCollapseFrom) {
            uint32_t total = 1;
            for (uint32_t i = 0; i < interior_count; ++i) total += count_below(interior[i], 1);
            return count_[source] = total;
        }
        for_each_index_on_threads(threads, interior_count, [&](size_t i) {
            count_below(interior[i], share_of(threads, interior[i], interior, interior_count));
        });
        uint32_t total = 1;
        for (uint32_t i = 0; i < interior_count; ++i) total += count_[interior[i]];
        return count_[source] = total;
    }

    // Writes the wide node of binary interior node `source` at `slot` and the count_[source] - 1 wide nodes below
    // it at [first, ...), in the order fill() appends them: its interior children side by side first, then the
    // nodes below each child in lane order. With threads to spare, the children's subtrees are written at the same
    // time (they know where they go from the counts), each with its share of the threads.
    void place(BvhWideNodes& wide, uint32_t slot, uint32_t source, uint32_t first, uint32_t threads) {
        if (threads <= 1 || range_[source].count < kParallelCollapseFrom) {
            uint32_t next = first;
            fill(wide, slot, source, next);
            return;
        }
        uint32_t interior[RT_BVH_WIDTH], below[RT_BVH_WIDTH];
        uint32_t interior_count = 0;
        wide[slot] = make_node(source, first, interior, interior_count);
        uint32_t next_below = first + interior_count;
        for (uint32_t i = 0; i < interior_count; ++i) {
            below[i] = next_below;
            next_below += count_[interior[i]] - 1;
        }
        for_each_index_on_threads(threads, interior_count, [&](size_t i) {
            place(wide, first + uint32_t(i), interior[i], below[i],
                  share_of(threads, interior[i], interior, interior_count));
        });
    }

    // A child's share of `threads` among the interior children `all`, by primitives (at least one).
    uint32_t share_of(uint32_t threads, uint32_t child, const uint32_t* all, uint32_t all_count) const {
        uint64_t primitives = 0;
        for (uint32_t i = 0; i < all_count; ++i) primitives += range_[all[i]].count;
        return uint32_t(std::max<uint64_t>(1, threads * uint64_t(range_[child].count) / primitives));
    }

    // The children a wide node takes for binary node `source`: its two, then the interior child with the largest
    // surface area (the likeliest to be entered) opened until there are RT_BVH_WIDTH or only leaves. Returns how
    // many.
    uint32_t open_children(uint32_t source, uint32_t (&children)[RT_BVH_WIDTH]) const {
        children[0] = lower_w(binary_[source]);
        children[1] = children[0] + 1;
        uint32_t count = 2;
        while (count < RT_BVH_WIDTH) {
            int widest = -1;
            float widest_area = -1.0f;
            for (uint32_t k = 0; k < count; ++k) {
                if (leaf(children[k])) continue;
                float area = area_[children[k]];
                if (area > widest_area) widest = int(k), widest_area = area;
            }
            if (widest < 0) break;
            uint32_t opened = children[widest];
            children[widest] = lower_w(binary_[opened]);
            children[count++] = lower_w(binary_[opened]) + 1;
        }
        return count;
    }

    // The wide node of binary interior node `source`: the children open_children() picks, a leaf one as a leaf lane,
    // the interior ones pointing at slots first, first + 1, ... in lane order. `interior` gets those children.
    BvhWideNode make_node(uint32_t source, uint32_t first, uint32_t (&interior)[RT_BVH_WIDTH],
                          uint32_t& interior_count) const {
        uint32_t children[RT_BVH_WIDTH];
        uint32_t count = open_children(source, children);
        BvhWideNode node = empty_;
        interior_count = 0;
        for (uint32_t k = 0; k < count; ++k) {
            if (leaf(children[k])) {
                set_leaf_lane(node, k, children[k]);
            } else {
                set_wide_lane_box(node, k, node_bounds(binary_[children[k]]));
                set_wide_lane_node(node, k, first + interior_count);
                interior[interior_count++] = children[k];
            }
        }
        return node;
    }

    // Writes the wide node of binary interior node `source` at `target` and the nodes below it from slot `next` on:
    // its interior children side by side, then the nodes below each of them in lane order, so a parent precedes its
    // children. Grows `wide` as needed (a collapse on one thread), or writes into it sized (place()).
    void fill(BvhWideNodes& wide, uint32_t target, uint32_t source, uint32_t& next) {
        uint32_t interior[RT_BVH_WIDTH];
        uint32_t interior_count = 0;
        const uint32_t first = next;
        BvhWideNode node = make_node(source, first, interior, interior_count);
        next += interior_count;
        if (wide.size() < next) wide.resize(next);
        wide[target] = node;
        for (uint32_t i = 0; i < interior_count; ++i) fill(wide, first + i, interior[i], next);
    }

    void set_leaf_lane(BvhWideNode& node, uint32_t k, uint32_t source) const {
        set_wide_lane_box(node, k, node_bounds(binary_[source]));
        set_wide_lane_leaf(node, k, range_[source].first, range_[source].count);
    }

    const BvhNodes& binary_;
    std::unique_ptr<Range[]> range_;
    std::unique_ptr<float[]> area_;      // each binary node's half area, looked up many times while opening children
    std::unique_ptr<uint32_t[]> count_;  // wide nodes under a binary node, where count_below() set it
    uint32_t leaf_size_;
    const BvhWideNode empty_ = empty_wide_node();
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

BvhWideNodes collapse_bvh_wide(const BvhNodes& stack_nodes, uint32_t leaf_size, uint32_t threads) {
    if (stack_nodes.empty()) throw Error("internal: collapsing an empty BVH");
    return Collapser(stack_nodes, std::min(leaf_size, RT_WIDE_LEAF_MAX), threads).run(threads);
}

uint32_t wide_stack_bound(const BvhWideNodes& wide, uint32_t root) {
    const BvhWideNode& node = wide.at(root);
    uint32_t used = 0, deepest = 0;
    for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
        if (!wide_lane_used(node, k)) continue;
        ++used;
        if (!wide_lane_leaf(node, k)) deepest = std::max(deepest, wide_stack_bound(wide, wide_lane_ref(node, k)));
    }
    return (used > 0 ? used - 1 : 0) + deepest;
}

void refit_bvh_wide(BvhWideNodes& wide, const std::vector<uint32_t>& primitive_order,
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
