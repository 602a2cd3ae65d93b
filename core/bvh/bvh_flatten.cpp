// Intermediate tree -> flat BvhNode arrays in the two layouts of kernels/types.h.
#include <bit>
#include <cfloat>

#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism {

namespace {

void set_w_bits(BvhNode& node, uint32_t lower_w, uint32_t upper_w) {
    node.lower.w = std::bit_cast<float>(lower_w);
    node.upper.w = std::bit_cast<float>(upper_w);
}

// Children sit in adjacent pairs allocated as their parent is written, so a parent always precedes its children
// and the two children of a node are fetched together.
void write_stack_layout(const BvhBuildNode& node, uint32_t index, std::vector<BvhNode>& nodes) {
    if (node.leaf()) {
        set_node_box(nodes[index], node.box);
        set_w_bits(nodes[index], node.first, node.count);
        return;
    }
    uint32_t first_child = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    set_node_box(nodes[index], node.box);
    set_w_bits(nodes[index], first_child, 0u);
    write_stack_layout(*node.children[0], first_child, nodes);
    write_stack_layout(*node.children[1], first_child + 1, nodes);
}

// Depth-first pre-order (thesis 6.4.1, Figure 6-14): the left child follows its parent, and the escape index is
// the first node after the subtree, where a traversal continues after a miss or a finished leaf.
void write_escape_layout(const BvhBuildNode& node, std::vector<BvhNode>& nodes) {
    uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    set_node_box(nodes[index], node.box);
    if (node.leaf()) {
        set_w_bits(nodes[index], index + 1, node.first | (node.count << RT_ESCAPE_COUNT_SHIFT));
        return;
    }
    write_escape_layout(*node.children[0], nodes);
    write_escape_layout(*node.children[1], nodes);
    set_w_bits(nodes[index], uint32_t(nodes.size()), RT_ESCAPE_INTERIOR);
}

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

std::vector<BvhNode> flatten_bvh_tree(const BvhTree& tree, BvhLayout layout) {
    std::vector<BvhNode> nodes;
    nodes.reserve(tree.node_count);
    if (layout == BvhLayout::Stack) {
        nodes.resize(1);
        write_stack_layout(*tree.root, 0, nodes);
    } else {
        write_escape_layout(*tree.root, nodes);
    }
    return nodes;
}

}  // namespace prism
