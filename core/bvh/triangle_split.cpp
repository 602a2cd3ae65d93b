// Triangle pre-splitting (triangle_split.h): Karras & Aila 2013's priorities and grid planes.
#include "core/bvh/triangle_split.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace prism {

namespace {

// Grid levels searched for a plane inside a box: 2^-24 of the scene is below float resolution anyway.
constexpr int kFinestLevel = 24;

// The dyadic grid over the scene box: level l has planes at lower + k * extent / 2^l on each axis.
struct Grid {
    glm::vec3 lower{0.0f}, extent{0.0f};

    // The coarsest level with a plane strictly inside (lo, hi) on `axis`, and that plane; level 0: none.
    int coarsest_plane(int axis, float lo, float hi, float& plane) const {
        if (!(extent[axis] > 0.0f) || !(hi > lo)) return 0;
        for (int level = 1; level <= kFinestLevel; ++level) {
            double cell = double(extent[axis]) / double(1u << level);
            // The first plane of this level above lo.
            double k = std::floor((double(lo) - double(lower[axis])) / cell) + 1.0;
            double position = double(lower[axis]) + k * cell;
            if (position > double(lo) && position < double(hi)) {
                plane = float(position);
                if (plane > lo && plane < hi) return level;
            }
        }
        return 0;
    }

    // The most important plane through a box: the coarsest level over the three axes (the longer axis on a tie).
    int best_plane(const Aabb& box, int& axis, float& plane) const {
        int best = 0;
        glm::vec3 size = box.upper - box.lower;
        for (int a = 0; a < 3; ++a) {
            float position = 0.0f;
            int level = coarsest_plane(a, box.lower[a], box.upper[a], position);
            if (level == 0) continue;
            if (best == 0 || level < best || (level == best && size[a] > size[axis])) {
                best = level;
                axis = a;
                plane = position;
            }
        }
        return best;
    }
};

// The triangle's part inside `box` on each side of the plane `axis` = `plane`, as boxes (the SBVH's clip: the
// vertices on each side and the edges' crossings, then cut to the box the part already had). Either can be empty.
void split_box(const TriangleCorners& t, const Aabb& box, int axis, float plane, Aabb& left, Aabb& right) {
    const glm::vec3 v[3] = {t.a, t.b, t.c};
    left = Aabb{};
    right = Aabb{};
    for (int i = 0; i < 3; ++i) {
        const glm::vec3& p = v[i];
        const glm::vec3& q = v[(i + 1) % 3];
        if (p[axis] <= plane) left.grow(p);
        if (p[axis] >= plane) right.grow(p);
        if ((p[axis] < plane && q[axis] > plane) || (p[axis] > plane && q[axis] < plane)) {
            float s = (plane - p[axis]) / (q[axis] - p[axis]);
            glm::vec3 crossing = p + s * (q - p);
            crossing[axis] = plane;
            left.grow(crossing);
            right.grow(crossing);
        }
    }
    left.lower = glm::max(left.lower, box.lower), left.upper = glm::min(left.upper, box.upper);
    right.lower = glm::max(right.lower, box.lower), right.upper = glm::min(right.upper, box.upper);
    left.upper[axis] = std::min(left.upper[axis], plane);
    right.lower[axis] = std::max(right.lower[axis], plane);
}

bool usable(const Aabb& box) {
    return box.lower.x <= box.upper.x && box.lower.y <= box.upper.y && box.lower.z <= box.upper.z;
}

float longest(const Aabb& box) {
    glm::vec3 size = box.upper - box.lower;
    return std::max(size.x, std::max(size.y, size.z));
}

// Cuts the box `splits` times at its most important planes, sharing the splits left after each cut between the
// two parts by their longest side (Karras & Aila's rule), and appends the resulting boxes.
void split_recursively(const TriangleCorners& t, const Aabb& box, uint32_t splits, const Grid& grid, uint32_t triangle,
                       SplitReferences& out) {
    int axis = 0;
    float plane = 0.0f;
    if (splits == 0 || grid.best_plane(box, axis, plane) == 0) {
        out.bounds.push_back(box);
        out.triangle.push_back(triangle);
        return;
    }
    Aabb left, right;
    split_box(t, box, axis, plane, left, right);
    bool has_left = usable(left), has_right = usable(right);
    if (!has_left || !has_right) {
        // The part of the triangle in this box lies on one side: the plane cuts only empty space.
        split_recursively(t, has_left ? left : has_right ? right : box, splits - 1, grid, triangle, out);
        return;
    }
    float wl = longest(left), wr = longest(right);
    uint32_t rest = splits - 1;
    uint32_t to_left = wl + wr > 0.0f ? uint32_t(std::lround(double(rest) * wl / (wl + wr))) : rest / 2;
    to_left = std::min(to_left, rest);
    split_recursively(t, left, to_left, grid, triangle, out);
    split_recursively(t, right, rest - to_left, grid, triangle, out);
}

}  // namespace

SplitReferences split_triangles(std::span<const TriangleCorners> corners, std::span<const Aabb> bounds,
                                float budget) {
    SplitReferences out;
    Aabb scene;
    size_t usable_triangles = 0;
    for (const Aabb& box : bounds)
        if (!box.empty()) scene.grow(box), ++usable_triangles;
    // Priorities: (2^-level x wasted area)^(1/3), the wasted area being the box's less the least any set of boxes
    // around the triangle could have (its projections on the three axis planes).
    std::vector<float> priority(bounds.size(), 0.0f);
    Grid grid;
    if (!scene.empty()) grid = Grid{scene.lower, scene.upper - scene.lower};
    double total = 0.0;
    if (budget > 0.0f)
        for (size_t t = 0; t < bounds.size(); ++t) {
            if (bounds[t].empty()) continue;
            glm::vec3 n = glm::cross(corners[t].b - corners[t].a, corners[t].c - corners[t].a);
            float ideal = 0.5f * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
            float wasted = bounds[t].half_area() - ideal;
            int axis = 0;
            float plane = 0.0f;
            int level = grid.best_plane(bounds[t], axis, plane);
            if (!(wasted > 0.0f) || level == 0) continue;
            priority[t] = float(std::cbrt(double(wasted) * std::ldexp(1.0, -level)));
            total += priority[t];
        }
    // Splits per triangle floor(scale x priority), the scale found by bisection so that they add up to the budget.
    const double wanted = double(budget) * double(usable_triangles);
    double scale = 0.0;
    if (total > 0.0 && wanted >= 1.0) {
        double lo = 0.0, hi = 2.0 * wanted / total + 1.0;
        for (int i = 0; i < 40; ++i) {
            double mid = 0.5 * (lo + hi), sum = 0.0;
            for (float p : priority) sum += std::floor(mid * p);
            (sum <= wanted ? lo : hi) = mid;
        }
        scale = lo;
    }
    out.bounds.reserve(usable_triangles + size_t(wanted) + 1);
    out.triangle.reserve(out.bounds.capacity());
    for (size_t t = 0; t < bounds.size(); ++t) {
        if (bounds[t].empty()) {
            // Left out by the builder, as without splitting: kept so that no split changes which triangles count.
            out.bounds.push_back(bounds[t]);
            out.triangle.push_back(uint32_t(t));
            continue;
        }
        uint32_t splits = uint32_t(std::min(std::floor(scale * priority[t]), 1024.0));
        split_recursively(corners[t], bounds[t], splits, grid, uint32_t(t), out);
    }
    return out;
}

namespace {

// A leaf's range in primitive_order, and where its node keeps it.
struct LeafRange {
    uint32_t first, count;
    uint32_t node, lane;  // lane: the wide layout's child; otherwise 0
};

}  // namespace

void map_split_references(Bvh& bvh, const SplitReferences& references) {
    std::vector<LeafRange> leaves;
    if (bvh.layout == BvhLayout::Wide) {
        for (uint32_t n = 0; n < bvh.wide_nodes.size(); ++n)
            for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k)
                if (wide_lane_leaf(bvh.wide_nodes[n], k))
                    leaves.push_back({wide_lane_first(bvh.wide_nodes[n], k), wide_lane_count(bvh.wide_nodes[n], k), n, k});
    } else {
        for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
            BvhNodeView view = decode_bvh_node(bvh, n);
            if (view.leaf) leaves.push_back({view.first, view.count, n, 0});
        }
    }
    // Leaves rewritten in the order of their ranges, each as its triangles without repeats: the ranges stay in
    // order and packed.
    std::sort(leaves.begin(), leaves.end(), [](const LeafRange& a, const LeafRange& b) { return a.first < b.first; });
    const std::vector<uint32_t> old_order = std::move(bvh.primitive_order);
    std::vector<uint32_t>& order = bvh.primitive_order;
    order.clear();
    order.reserve(old_order.size());
    for (const LeafRange& leaf : leaves) {
        uint32_t first = uint32_t(order.size());
        for (uint32_t i = 0; i < leaf.count; ++i) {
            uint32_t triangle = references.triangle[old_order[leaf.first + i]];
            if (std::find(order.begin() + first, order.end(), triangle) == order.end()) order.push_back(triangle);
        }
        uint32_t count = uint32_t(order.size()) - first;
        if (bvh.layout == BvhLayout::Wide) {
            set_wide_lane_leaf(bvh.wide_nodes[leaf.node], leaf.lane, first, count);
            continue;
        }
        BvhNode& node = bvh.nodes[leaf.node];
        node.lower.w = std::bit_cast<float>(bvh.layout == BvhLayout::Stack ? first
                                                                           : std::bit_cast<uint32_t>(node.lower.w));
        node.upper.w = std::bit_cast<float>(bvh.layout == BvhLayout::Stack ? count
                                                                           : first | count << RT_ESCAPE_COUNT_SHIFT);
    }
    // The binary tree's cost as the walk pays it, a triangle once per leaf (the wide layout keeps the build's).
    if (bvh.layout != BvhLayout::Wide) bvh.sah_cost = sah_cost(bvh, bvh.options);
}

}  // namespace prism
