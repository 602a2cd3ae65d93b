// Work on a flat BVH after the build: refit, SAH cost, node decoding.
#include <algorithm>
#include <bit>
#include <string>
#include <thread>

#include "core/bvh/bvh.h"
#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"
#include "core/util/parallel_indices.h"

namespace prism {

Aabb node_bounds(const BvhNode& node) {
    Aabb box;
    box.lower = {node.lower.x, node.lower.y, node.lower.z};
    box.upper = {node.upper.x, node.upper.y, node.upper.z};
    return box;
}

BvhNodeView decode_bvh_node(const Bvh& bvh, uint32_t index) {
    const BvhNode& node = bvh.nodes[index];
    uint32_t lower_w = std::bit_cast<uint32_t>(node.lower.w);
    uint32_t upper_w = std::bit_cast<uint32_t>(node.upper.w);
    BvhNodeView view;
    if (bvh.layout != BvhLayout::Escape) {  // the wide layout keeps its binary tree in the stack layout
        // The empty BVH's single node has count 0 yet is a leaf: it is the only node without children.
        view.leaf = upper_w != 0 || bvh.nodes.size() == 1;
        if (view.leaf) {
            view.first = lower_w;
            view.count = upper_w;
        } else {
            view.left = lower_w;
            view.right = lower_w + 1;
        }
    } else {
        view.leaf = upper_w != RT_ESCAPE_INTERIOR;
        if (view.leaf) {
            view.first = upper_w & RT_ESCAPE_FIRST_MASK;
            view.count = upper_w >> RT_ESCAPE_COUNT_SHIFT;
        } else {
            view.left = index + 1;
            view.right = std::bit_cast<uint32_t>(bvh.nodes[index + 1].lower.w);  // the left subtree's escape
        }
    }
    return view;
}

void refit_bvh(Bvh& bvh, std::span<const Aabb> primitive_bounds) {
    if (primitive_bounds.size() != bvh.primitive_count)
        throw Error("BVH refit: got " + std::to_string(primitive_bounds.size()) +
                    " primitive bounds, the BVH was built over " + std::to_string(bvh.primitive_count));
    // Children always follow their parent in both layouts, so one reverse sweep sees children first.
    for (uint32_t index = uint32_t(bvh.nodes.size()); index-- > 0;) {
        BvhNodeView view = decode_bvh_node(bvh, index);
        Aabb box;
        if (view.leaf) {
            for (uint32_t i = view.first; i < view.first + view.count; ++i) {
                const Aabb& primitive = primitive_bounds[bvh.primitive_order[i]];
                if (bvh_usable_bounds(primitive)) box.grow(primitive);
            }
        } else {
            for (uint32_t child : {view.left, view.right}) {
                Aabb child_box = node_bounds(bvh.nodes[child]);
                if (!child_box.empty()) box.grow(child_box);
            }
        }
        set_node_box(bvh.nodes[index], box);
    }
    if (bvh.layout == BvhLayout::Wide) refit_bvh_wide(bvh.wide_nodes, bvh.primitive_order, primitive_bounds);
    bvh.sah_cost = sah_cost(bvh, bvh.options);
}

float sah_cost(const Bvh& bvh, const BvhBuildOptions& options) {
    if (bvh.nodes.empty()) return 0.0f;
    float root_area = node_bounds(bvh.nodes[0]).half_area();
    if (!(root_area > 0.0f)) return 0.0f;  // empty tree (or only points): no ray hits it
    // Summed in double (a million terms in float would lose the small ones), per chunk of a fixed size on up to
    // bvh.options.threads threads, then chunk by chunk in order: the same sum for any thread count.
    constexpr uint32_t kChunk = 1u << 16;
    const uint32_t node_count = uint32_t(bvh.nodes.size());
    const uint32_t chunks = (node_count + kChunk - 1) / kChunk;
    std::vector<double> interior(chunks), leaves(chunks);
    uint32_t threads = bvh.options.threads != 0 ? bvh.options.threads : std::thread::hardware_concurrency();
    for_each_index_on_threads(threads, chunks, [&](size_t chunk) {
        double interior_part = 0.0, leaves_part = 0.0;
        for (uint32_t index = uint32_t(chunk) * kChunk; index < std::min(node_count, uint32_t(chunk + 1) * kChunk);
             ++index) {
            BvhNodeView view = decode_bvh_node(bvh, index);
            double area = node_bounds(bvh.nodes[index]).half_area();
            if (view.leaf)
                leaves_part += area * view.count;
            else
                interior_part += area;
        }
        interior[chunk] = interior_part, leaves[chunk] = leaves_part;
    });
    double interior_sum = 0.0, leaves_sum = 0.0;
    for (uint32_t chunk = 0; chunk < chunks; ++chunk) interior_sum += interior[chunk], leaves_sum += leaves[chunk];
    return float((options.traversal_cost * interior_sum + options.intersection_cost * leaves_sum) / root_area);
}

}  // namespace prism
