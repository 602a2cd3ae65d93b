// Intermediate tree -> flat BvhNode arrays in the two layouts of kernels/types.h.
#include <algorithm>
#include <bit>
#include <cfloat>
#include <thread>

#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism {

namespace {

void set_w_bits(BvhNode& node, uint32_t lower_w, uint32_t upper_w) {
    node.lower.w = std::bit_cast<float>(lower_w);
    node.upper.w = std::bit_cast<float>(upper_w);
}

// Subtrees with at least this many nodes may be written on a thread of their own.
constexpr uint32_t kParallelSubtreeFrom = 1u << 14;

// Writes each subtree where the one-thread recursion would, from the subtree sizes the builders record: so large
// subtrees can be written at the same time, on `threads` threads at most (each split hands half its threads to the
// left child), with the same array as a result.
class Flattener {
public:
    explicit Flattener(BvhNodes& nodes) : nodes_(nodes) {}

    // Children sit in adjacent pairs allocated as their parent is written, so a parent always precedes its
    // children and the two children of a node are fetched together. `next`: where the pairs below `node` begin.
    void write_stack(const BvhBuildNode& node, uint32_t index, uint32_t next, uint32_t threads) {
        set_node_box(nodes_[index], node.box);
        if (node.leaf()) {
            set_w_bits(nodes_[index], node.first, node.count);
            return;
        }
        const uint32_t first_child = next;
        set_w_bits(nodes_[index], first_child, 0u);
        const BvhBuildNode& left = *node.children[0];
        const BvhBuildNode& right = *node.children[1];
        // The left child's pairs come first: its subtree less itself.
        const uint32_t left_next = first_child + 2, right_next = left_next + left.nodes - 1;
        both(
            left, right, threads, [&](uint32_t t) { write_stack(left, first_child, left_next, t); },
            [&](uint32_t t) { write_stack(right, first_child + 1, right_next, t); });
    }

    // Depth-first pre-order (thesis 6.4.1, Figure 6-14): the left child follows its parent, and the escape index is
    // the first node after the subtree, where a traversal continues after a miss or a finished leaf.
    void write_escape(const BvhBuildNode& node, uint32_t index, uint32_t threads) {
        set_node_box(nodes_[index], node.box);
        if (node.leaf()) {
            set_w_bits(nodes_[index], index + 1, node.first | (node.count << RT_ESCAPE_COUNT_SHIFT));
            return;
        }
        set_w_bits(nodes_[index], index + node.nodes, RT_ESCAPE_INTERIOR);
        const BvhBuildNode& left = *node.children[0];
        const BvhBuildNode& right = *node.children[1];
        both(
            left, right, threads, [&](uint32_t t) { write_escape(left, index + 1, t); },
            [&](uint32_t t) { write_escape(right, index + 1 + left.nodes, t); });
    }

private:
    template <class Left, class Right>
    static void both(const BvhBuildNode& left, const BvhBuildNode& right, uint32_t threads, const Left& write_left,
                     const Right& write_right) {
        if (threads < 2 || left.nodes < kParallelSubtreeFrom || right.nodes < kParallelSubtreeFrom) {
            write_left(threads);
            write_right(threads);
            return;
        }
        std::thread worker([&] { write_left(threads / 2); });
        write_right(threads - threads / 2);
        worker.join();
    }

    BvhNodes& nodes_;
};

}  // namespace

void set_node_box(BvhNode& node, const Aabb& box) {
    if (box.empty()) {
        node.lower.x = node.lower.y = node.lower.z = FLT_MAX;
        node.upper.x = node.upper.y = node.upper.z = -FLT_MAX;
        return;
    }
    node.lower.x = box.lower.x, node.lower.y = box.lower.y, node.lower.z = box.lower.z;
    node.upper.x = box.upper.x, node.upper.y = box.upper.y, node.upper.z = box.upper.z;
}

BvhNodes flatten_bvh_tree(const BvhTree& tree, BvhLayout layout, uint32_t threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    BvhNodes nodes(tree.root->nodes);
    Flattener flattener(nodes);
    if (layout == BvhLayout::Stack)
        flattener.write_stack(*tree.root, 0, 1, threads);
    else
        flattener.write_escape(*tree.root, 0, threads);
    return nodes;
}

}  // namespace prism
