// BVH builders and flat layouts: structure invariants read straight from the node bits, closest hits of a small
// traversal of each layout against brute force, refit, determinism across thread counts, SAH vs the seed's median.
#include "core/bvh/bvh.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "core/loaders/load_ply.h"
#include "tests/test_support.h"

namespace prism {
namespace {

// Byte equality of two node arrays (empty ones included: memcmp must not see their null data()).
template <typename T, typename A>
bool same_bytes(const std::vector<T, A>& a, const std::vector<T, A>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

struct Triangle {
    glm::vec3 a, b, c;
};

// Triangles and the bounds the caller hands the builder: empty for degenerate triangles (the caller's
// convention), non-finite where a vertex is.
struct Soup {
    std::vector<Triangle> triangles;
    std::vector<Aabb> bounds;
};

bool usable(const Aabb& box) {
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(box.lower[axis]) || !std::isfinite(box.upper[axis])) return false;
        if (box.lower[axis] > box.upper[axis]) return false;
    }
    return true;
}

Aabb caller_bounds(const Triangle& t) {
    Aabb box;
    for (const glm::vec3& v : {t.a, t.b, t.c}) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y) ||
            !std::isfinite(v.z)) {  // grow() would drop a NaN (glm::min keeps the other operand)
            box.lower = box.upper = glm::vec3(std::numeric_limits<float>::quiet_NaN());
            return box;
        }
    }
    if (glm::length(glm::cross(t.b - t.a, t.c - t.a)) == 0.0f) return box;  // degenerate: empty bounds
    box.grow(t.a);
    box.grow(t.b);
    box.grow(t.c);
    return box;
}

Soup make_soup(std::vector<Triangle> triangles) {
    Soup soup;
    soup.triangles = std::move(triangles);
    for (const auto& t : soup.triangles) soup.bounds.push_back(caller_bounds(t));
    return soup;
}

// Clustered random triangles of mixed sizes, with some degenerate and some non-finite ones mixed in.
Soup random_soup(uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<glm::vec3> clusters;
    for (int i = 0; i < 8; ++i) clusters.push_back({unit(rng) * 20 - 10, unit(rng) * 20 - 10, unit(rng) * 20 - 10});
    std::vector<Triangle> triangles;
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec3 center =
            clusters[i % clusters.size()] + glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f) * 6.0f;
        float size = (i % 10 == 0) ? 2.0f : 0.2f;
        auto corner = [&] { return center + glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f) * size; };
        Triangle t{corner(), corner(), corner()};
        if (i % 17 == 3) t.b = t.c = t.a;                                  // degenerate
        if (i % 29 == 5) t.c.y = std::numeric_limits<float>::quiet_NaN();  // non-finite
        triangles.push_back(t);
    }
    return make_soup(std::move(triangles));
}

const Soup& bunny() {
    static const Soup soup = [] {
        Mesh mesh = load_ply(test::scene("stanford/bunny.ply"));
        std::vector<Triangle> triangles;
        for (const auto& index : mesh.triangles)
            triangles.push_back({mesh.positions[index.x], mesh.positions[index.y], mesh.positions[index.z]});
        return make_soup(std::move(triangles));
    }();
    return soup;
}

BvhBuildOptions options_for(BvhMethod method, BvhLayout layout, uint32_t threads = 0) {
    BvhBuildOptions options;
    options.method = method;
    options.layout = layout;
    options.threads = threads;
    return options;
}

// ---- Reading the node bits the way a traversal does -----------------------------------------------------------

uint32_t bits(float value) { return std::bit_cast<uint32_t>(value); }

Aabb box_of(const BvhNode& node) {
    Aabb box;
    box.lower = {node.lower.x, node.lower.y, node.lower.z};
    box.upper = {node.upper.x, node.upper.y, node.upper.z};
    return box;
}

bool contains(const Aabb& outer, const Aabb& inner) {
    return glm::all(glm::lessThanEqual(outer.lower, inner.lower)) &&
           glm::all(glm::greaterThanEqual(outer.upper, inner.upper));
}

struct Leaf {
    uint32_t first, count;
};

// Checks one leaf's range: within primitive_order, non-empty, within the size limit, its box holds its primitives.
void check_leaf(const Bvh& bvh, std::span<const Aabb> bounds, const BvhNode& node, Leaf leaf, uint32_t max_leaf,
                std::vector<int>& references) {
    ASSERT_GE(leaf.count, 1u);
    ASSERT_LE(leaf.count, max_leaf);
    ASSERT_LE(uint64_t(leaf.first) + leaf.count, bvh.primitive_order.size());
    for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
        uint32_t primitive = bvh.primitive_order[i];
        ASSERT_LT(primitive, bounds.size());
        references[primitive]++;
        if (usable(bounds[primitive])) {
            EXPECT_TRUE(contains(box_of(node), bounds[primitive])) << "leaf box";
        }
    }
}

// ---- The wide layout's nodes, decoded from kernels/types.h alone ------------------------------------------------

float wide_lane(const float4& lanes_0_3, const float4& lanes_4_7, uint32_t k) {
    const float4& v = k < 4 ? lanes_0_3 : lanes_4_7;
    float lanes[4] = {v.x, v.y, v.z, v.w};
    return lanes[k & 3];
}

uint32_t wide_ref(const BvhWideNode& node, uint32_t k) {
    const uint4& v = k < 4 ? node.child0 : node.child1;
    uint32_t lanes[4] = {v.x, v.y, v.z, v.w};
    return lanes[k & 3];
}

// The lane's box as a binary node (the tiny tracer's slab test takes those).
BvhNode wide_box(const BvhWideNode& node, uint32_t k) {
    BvhNode box{};
    box.lower = {wide_lane(node.lower_x0, node.lower_x1, k), wide_lane(node.lower_y0, node.lower_y1, k),
                 wide_lane(node.lower_z0, node.lower_z1, k), 0.0f};
    box.upper = {wide_lane(node.upper_x0, node.upper_x1, k), wide_lane(node.upper_y0, node.upper_y1, k),
                 wide_lane(node.upper_z0, node.upper_z1, k), 0.0f};
    return box;
}

// Every node reached once from the root, after its parent; a used lane's box holds its child's (non-empty) lanes
// or its leaf's primitives; an unused lane is +inf in all six and refers to nothing; leaves hold 1..8 primitives, and
// together every primitive the binary tree holds, once.
void check_wide_structure(const Bvh& bvh, std::span<const Aabb> bounds, uint32_t max_leaf,
                          const std::vector<bool>& referenced) {
    const auto& wide = bvh.wide_nodes;
    ASSERT_FALSE(wide.empty());
    std::vector<int> references(bounds.size(), 0), visits(wide.size(), 0);
    std::vector<uint32_t> stack{0};
    const float inf = std::numeric_limits<float>::infinity();
    while (!stack.empty()) {
        uint32_t index = stack.back();
        stack.pop_back();
        visits[index]++;
        const BvhWideNode& node = wide[index];
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            uint32_t ref = wide_ref(node, k);
            BvhNode lane = wide_box(node, k);
            if (ref == 0) {
                for (float bound : {lane.lower.x, lane.lower.y, lane.lower.z, lane.upper.x, lane.upper.y, lane.upper.z})
                    EXPECT_EQ(bound, inf) << "unused lane " << k << " of node " << index;
                continue;
            }
            if (ref & RT_WIDE_LEAF) {
                uint32_t first = (ref & ~RT_WIDE_LEAF) >> 3, count = (ref & 7u) + 1;
                // Subtrees of up to wide_leaf_size primitives are merged into one leaf.
                check_leaf(bvh, bounds, lane, {first, count},
                           std::min(std::max(max_leaf, bvh.options.wide_leaf_size), RT_WIDE_LEAF_MAX), references);
                continue;
            }
            ASSERT_GT(ref, index) << "children follow their parent";
            ASSERT_LT(ref, wide.size());
            for (uint32_t c = 0; c < RT_BVH_WIDTH; ++c) {
                // A used lane may be empty (+inf) after a refit made all its primitives degenerate.
                if (wide_ref(wide[ref], c) != 0 && wide_box(wide[ref], c).lower.x != inf) {
                    EXPECT_TRUE(contains(box_of(lane), box_of(wide_box(wide[ref], c)))) << "child lane " << c;
                }
            }
            stack.push_back(ref);
        }
    }
    for (size_t i = 0; i < wide.size(); ++i) EXPECT_EQ(visits[i], 1) << "wide node " << i << " reached once";
    for (size_t i = 0; i < bounds.size(); ++i) EXPECT_EQ(references[i], referenced[i] ? 1 : 0) << "primitive " << i;
}

// The invariants of both layouts, decoded independently of core/ (kernels/types.h is the contract).
// `referenced` says which primitives the leaves must hold (default: those with usable bounds). Returns the depth.
uint32_t check_structure(const Bvh& bvh, std::span<const Aabb> bounds, uint32_t max_leaf,
                         std::vector<bool> referenced = {}) {
    if (referenced.empty())
        for (const auto& box : bounds) referenced.push_back(usable(box));
    const auto& nodes = bvh.nodes;
    EXPECT_FALSE(nodes.empty());
    if (nodes.empty()) return 0;
    std::vector<int> references(bounds.size(), 0);
    std::vector<int> visits(nodes.size(), 0);
    uint32_t depth = 0;
    struct Entry {
        uint32_t index, depth;
    };
    std::vector<Entry> stack{{0, 1}};
    while (!stack.empty()) {
        Entry entry = stack.back();
        stack.pop_back();
        depth = std::max(depth, entry.depth);
        const BvhNode& node = nodes[entry.index];
        visits[entry.index]++;
        uint32_t lower_w = bits(node.lower.w), upper_w = bits(node.upper.w);
        uint32_t children[2];
        if (bvh.layout != BvhLayout::Escape) {  // the wide layout keeps its binary tree in the stack layout
            if (upper_w != 0) {
                check_leaf(bvh, bounds, node, {lower_w, upper_w}, max_leaf, references);
                continue;
            }
            EXPECT_GT(lower_w, entry.index) << "children follow their parent";
            EXPECT_LT(uint64_t(lower_w) + 1, nodes.size());
            if (lower_w <= entry.index || uint64_t(lower_w) + 1 >= nodes.size()) return depth;
            children[0] = lower_w;
            children[1] = lower_w + 1;
        } else {
            uint32_t escape = lower_w;
            EXPECT_GT(escape, entry.index);
            EXPECT_LE(escape, nodes.size());
            if (escape <= entry.index || escape > nodes.size()) return depth;
            if (upper_w != RT_ESCAPE_INTERIOR) {
                EXPECT_EQ(escape, entry.index + 1) << "a leaf escapes to the next node";
                check_leaf(bvh, bounds, node, {upper_w & RT_ESCAPE_FIRST_MASK, upper_w >> RT_ESCAPE_COUNT_SHIFT},
                           std::min(max_leaf, 255u), references);
                continue;
            }
            children[0] = entry.index + 1;
            EXPECT_LT(children[0], escape) << "an interior node has a left child inside its subtree";
            if (children[0] >= escape) return depth;
            children[1] = bits(nodes[children[0]].lower.w);  // the left subtree ends where the right begins
            EXPECT_LT(children[1], escape);
            if (children[1] >= escape) return depth;
            EXPECT_EQ(bits(nodes[children[1]].lower.w), escape) << "the right subtree ends with its parent's";
        }
        for (uint32_t child : children) {
            EXPECT_TRUE(contains(box_of(node), box_of(nodes[child]))) << "child " << child << " in " << entry.index;
            stack.push_back({child, entry.depth + 1});
        }
    }
    if (bvh.layout == BvhLayout::Escape) {
        EXPECT_EQ(bits(nodes[0].lower.w), nodes.size()) << "root escape";
    }
    for (size_t i = 0; i < nodes.size(); ++i) EXPECT_EQ(visits[i], 1) << "node " << i << " reached once";
    size_t expected_count = 0;
    for (size_t i = 0; i < bounds.size(); ++i) {
        expected_count += referenced[i];
        EXPECT_EQ(references[i], referenced[i] ? 1 : 0) << "primitive " << i;
    }
    EXPECT_EQ(bvh.primitive_order.size(), expected_count);
    EXPECT_EQ(bvh.depth, depth);
    if (bvh.layout == BvhLayout::Wide)
        check_wide_structure(bvh, bounds, max_leaf, referenced);
    else
        EXPECT_TRUE(bvh.wide_nodes.empty());
    return depth;
}

// ---- A tiny tracer: rays, slab test, Möller-Trumbore, one traversal per layout --------------------------------

struct Ray {
    glm::vec3 origin, direction;
};

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    uint32_t primitive = UINT32_MAX;
    // Equal distances go to the lower index, so every traversal order agrees with brute force exactly.
    void offer(float candidate, uint32_t index) {
        if (!std::isfinite(candidate)) return;
        if (candidate < t || (candidate == t && index < primitive)) t = candidate, primitive = index;
    }
};

float intersect_triangle(const Ray& ray, const Triangle& tri) {
    const float none = std::numeric_limits<float>::infinity();
    glm::vec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
    glm::vec3 p = glm::cross(ray.direction, e2);
    float det = glm::dot(e1, p);
    if (det == 0.0f) return none;
    float inverse = 1.0f / det;
    glm::vec3 s = ray.origin - tri.a;
    float u = glm::dot(s, p) * inverse;
    if (u < 0.0f || u > 1.0f) return none;
    glm::vec3 q = glm::cross(s, e1);
    float v = glm::dot(ray.direction, q) * inverse;
    if (v < 0.0f || u + v > 1.0f) return none;
    float t = glm::dot(e2, q) * inverse;
    return t > 0.0f ? t : none;
}

// Slab test that picks the near plane by the sign of the direction (Williams et al. 2005, Shirley's form), so an
// inverted box (lower > upper, the empty BVH's root) is missed. The min/max form would take it for the box
// between its corners and hit it. The far distance is widened by a few ulps so rounding never culls a box that
// holds a hit (PBRT's 1 + 2 gamma(3)).
bool hits_box(const Ray& ray, const BvhNode& node, float t_max) {
    glm::vec3 inverse = 1.0f / ray.direction;
    glm::vec3 lower{node.lower.x, node.lower.y, node.lower.z}, upper{node.upper.x, node.upper.y, node.upper.z};
    float enter = 0.0f, leave = t_max;
    for (int axis = 0; axis < 3; ++axis) {
        bool negative = inverse[axis] < 0.0f;
        float near = ((negative ? upper : lower)[axis] - ray.origin[axis]) * inverse[axis];
        float far = ((negative ? lower : upper)[axis] - ray.origin[axis]) * inverse[axis];
        enter = std::max(enter, near);
        leave = std::min(leave, far);
    }
    return enter <= leave * (1.0f + 4.0f * FLT_EPSILON);
}

void test_leaf(const Ray& ray, const Soup& soup, const Bvh& bvh, uint32_t first, uint32_t count, Hit& hit) {
    for (uint32_t i = first; i < first + count; ++i) {
        uint32_t primitive = bvh.primitive_order[i];
        hit.offer(intersect_triangle(ray, soup.triangles[primitive]), primitive);
    }
}

// Depth first from the root (node 0): visit(index, stack) is given each node popped and pushes what comes next.
template <typename Visit>
void walk_from_root(Visit visit) {
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        uint32_t index = stack.back();
        stack.pop_back();
        visit(index, stack);
    }
}

Hit trace_stack_layout(const Ray& ray, const Soup& soup, const Bvh& bvh) {
    Hit hit;
    walk_from_root([&](uint32_t index, std::vector<uint32_t>& stack) {
        const BvhNode& node = bvh.nodes[index];
        if (!hits_box(ray, node, hit.t)) return;
        uint32_t first = bits(node.lower.w), count = bits(node.upper.w);
        if (count != 0) {
            test_leaf(ray, soup, bvh, first, count, hit);
        } else {
            stack.push_back(first + 1);
            stack.push_back(first);
        }
    });
    return hit;
}

Hit trace_escape_layout(const Ray& ray, const Soup& soup, const Bvh& bvh) {
    Hit hit;
    uint32_t index = 0;
    while (index < bvh.nodes.size()) {
        const BvhNode& node = bvh.nodes[index];
        uint32_t escape = bits(node.lower.w), info = bits(node.upper.w);
        if (!hits_box(ray, node, hit.t)) {
            index = escape;
        } else if (info == RT_ESCAPE_INTERIOR) {
            index++;
        } else {
            test_leaf(ray, soup, bvh, info & RT_ESCAPE_FIRST_MASK, info >> RT_ESCAPE_COUNT_SHIFT, hit);
            index = escape;
        }
    }
    return hit;
}

Hit trace_wide_layout(const Ray& ray, const Soup& soup, const Bvh& bvh) {
    Hit hit;
    walk_from_root([&](uint32_t index, std::vector<uint32_t>& stack) {
        const BvhWideNode& node = bvh.wide_nodes[index];
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            uint32_t ref = wide_ref(node, k);
            if (ref == 0 || !hits_box(ray, wide_box(node, k), hit.t)) continue;
            if (ref & RT_WIDE_LEAF)
                test_leaf(ray, soup, bvh, (ref & ~RT_WIDE_LEAF) >> 3, (ref & 7u) + 1, hit);
            else
                stack.push_back(ref);
        }
    });
    return hit;
}

Hit trace_brute_force(const Ray& ray, const Soup& soup) {
    Hit hit;
    for (uint32_t i = 0; i < soup.triangles.size(); ++i)
        if (usable(soup.bounds[i])) hit.offer(intersect_triangle(ray, soup.triangles[i]), i);
    return hit;
}

// Half the rays start anywhere around the scene, half aim at a random triangle so most of them hit something.
std::vector<Ray> random_rays(const Soup& soup, uint32_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    Aabb scene;
    std::vector<uint32_t> targets;
    for (uint32_t i = 0; i < soup.bounds.size(); ++i) {
        if (!usable(soup.bounds[i])) continue;
        scene.grow(soup.bounds[i]);
        targets.push_back(i);
    }
    glm::vec3 size = scene.upper - scene.lower;
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < count; ++i) {
        glm::vec3 origin = scene.lower - 0.5f * size + 2.0f * size * glm::vec3(unit(rng), unit(rng), unit(rng));
        glm::vec3 direction;
        if (i % 2 == 0 && !targets.empty()) {
            const Triangle& t = soup.triangles[targets[rng() % targets.size()]];
            float u = unit(rng), v = unit(rng) * (1.0f - u);
            direction = t.a + u * (t.b - t.a) + v * (t.c - t.a) - origin;
        } else {
            direction = glm::vec3(unit(rng), unit(rng), unit(rng)) - 0.5f;
        }
        rays.push_back({origin, glm::normalize(direction)});
    }
    return rays;
}

// Closest hits through the BVH equal brute force exactly (same triangle test, same tie rule).
void check_closest_hits(const Bvh& bvh, const Soup& soup, uint32_t ray_count) {
    uint32_t hits = 0;
    for (const Ray& ray : random_rays(soup, ray_count, 7)) {
        Hit expected = trace_brute_force(ray, soup);
        Hit got = bvh.layout == BvhLayout::Stack    ? trace_stack_layout(ray, soup, bvh)
                  : bvh.layout == BvhLayout::Escape ? trace_escape_layout(ray, soup, bvh)
                                                    : trace_wide_layout(ray, soup, bvh);
        ASSERT_EQ(got.primitive, expected.primitive);
        ASSERT_EQ(got.t, expected.t);
        hits += expected.primitive != UINT32_MAX;
    }
    EXPECT_GT(hits, ray_count / 4) << "too few rays hit for the comparison to mean much";
}

const BvhMethod kMethods[] = {BvhMethod::BinnedSah, BvhMethod::Median};
const BvhLayout kLayouts[] = {BvhLayout::Stack, BvhLayout::Escape, BvhLayout::Wide};

std::string describe(BvhMethod method, BvhLayout layout) {
    return std::string(method == BvhMethod::BinnedSah ? "sah" : "median") + "/" +
           (layout == BvhLayout::Stack    ? "stack"
            : layout == BvhLayout::Escape ? "escape"
                                          : "wide");
}

// ---- Tests --------------------------------------------------------------------------------------------------

TEST(BvhBuild, RandomSoupEveryMethodAndLayout) {
    Soup soup = random_soup(20000, 1);
    for (BvhMethod method : kMethods) {
        for (BvhLayout layout : kLayouts) {
            SCOPED_TRACE(describe(method, layout));
            Bvh bvh = build_bvh(soup.bounds, options_for(method, layout));
            EXPECT_EQ(bvh.layout, layout);
            EXPECT_EQ(bvh.primitive_count, soup.bounds.size());
            check_structure(bvh, soup.bounds, 4);
            check_closest_hits(bvh, soup, 400);
            EXPECT_GT(bvh.sah_cost, 0.0f);
        }
    }
}

TEST(BvhBuild, BunnyEveryMethodAndLayout) {
    const Soup& soup = bunny();
    ASSERT_EQ(soup.triangles.size(), 69451u);
    for (BvhMethod method : kMethods) {
        for (BvhLayout layout : kLayouts) {
            SCOPED_TRACE(describe(method, layout));
            Bvh bvh = build_bvh(soup.bounds, options_for(method, layout));
            uint32_t depth = check_structure(bvh, soup.bounds, 4);
            EXPECT_LE(depth, uint32_t(RT_BVH_STACK_SIZE)) << "a stack traversal must not overflow";
            check_closest_hits(bvh, soup, 200);
        }
    }
}

TEST(BvhBuild, SahIsCheaperThanTheSeedsMedianSplitOnTheBunny) {
    const Soup& soup = bunny();
    Bvh sah = build_bvh(soup.bounds, options_for(BvhMethod::BinnedSah, BvhLayout::Stack));
    Bvh median = build_bvh(soup.bounds, options_for(BvhMethod::Median, BvhLayout::Stack));
    EXPECT_LT(sah.sah_cost, median.sah_cost);
    EXPECT_FLOAT_EQ(sah.sah_cost, sah_cost(sah, BvhBuildOptions{}));
}

// The steps' times add up to at most the whole build's, and only the wide layout collapses.
TEST(BvhBuild, PhasesAccountForTheBuildTime) {
    const Soup& soup = bunny();
    for (BvhLayout layout : kLayouts) {
        SCOPED_TRACE(describe(BvhMethod::BinnedSah, layout));
        Bvh bvh = build_bvh(soup.bounds, options_for(BvhMethod::BinnedSah, layout));
        const BvhBuildPhases& p = bvh.phases;
        EXPECT_GT(p.tree_ms, 0.0);
        EXPECT_GE(p.flatten_ms, 0.0);
        EXPECT_GE(p.sah_ms, 0.0);
        EXPECT_EQ(p.collapse_ms > 0.0, layout == BvhLayout::Wide);
        EXPECT_LE(p.tree_ms + p.flatten_ms + p.collapse_ms + p.sah_ms, bvh.build_ms);
    }
}

TEST(BvhBuild, SameNodesForAnyThreadCount) {
    const Soup& bunny_soup = bunny();
    Soup large = random_soup(150000, 2);  // chunked binning and partitions at the top, subtrees flattened apart
    for (const Soup* soup : {&bunny_soup, const_cast<const Soup*>(&large)}) {
        for (BvhMethod method : kMethods) {
            for (BvhLayout layout : kLayouts) {
                SCOPED_TRACE(describe(method, layout));
                Bvh one = build_bvh(soup->bounds, options_for(method, layout, 1));
                for (uint32_t threads : {2u, 5u}) {
                    Bvh many = build_bvh(soup->bounds, options_for(method, layout, threads));
                    ASSERT_EQ(one.nodes.size(), many.nodes.size());
                    EXPECT_TRUE(same_bytes(one.nodes, many.nodes));
                    EXPECT_EQ(one.primitive_order, many.primitive_order);
                    EXPECT_EQ(one.sah_cost, many.sah_cost);
                    ASSERT_EQ(one.wide_nodes.size(), many.wide_nodes.size());
                    EXPECT_TRUE(same_bytes(one.wide_nodes, many.wide_nodes));
                }
            }
        }
    }
}

TEST(BvhBuild, NoUsablePrimitiveGivesOneLeafNoRayHits) {
    std::vector<Aabb> nothing;
    std::vector<Aabb> all_left_out(5);  // default Aabb: empty
    all_left_out[1].lower = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    all_left_out[1].upper = glm::vec3(1.0f);
    for (const auto* input : {&nothing, &all_left_out}) {
        for (BvhMethod method : kMethods) {
            for (BvhLayout layout : kLayouts) {
                SCOPED_TRACE(describe(method, layout));
                Bvh bvh = build_bvh(*input, options_for(method, layout));
                ASSERT_EQ(bvh.nodes.size(), 1u);
                const BvhNode& node = bvh.nodes[0];
                EXPECT_EQ(node.lower.x, FLT_MAX);
                EXPECT_EQ(node.lower.z, FLT_MAX);
                EXPECT_EQ(node.upper.x, -FLT_MAX);
                EXPECT_EQ(node.upper.y, -FLT_MAX);
                EXPECT_TRUE(bvh.primitive_order.empty());
                EXPECT_EQ(bvh.sah_cost, 0.0f);
                BvhNodeView view = decode_bvh_node(bvh, 0);
                EXPECT_TRUE(view.leaf);
                EXPECT_EQ(view.count, 0u);
                if (layout == BvhLayout::Escape) {
                    EXPECT_EQ(bits(node.lower.w), 1u);
                    EXPECT_EQ(bits(node.upper.w) >> RT_ESCAPE_COUNT_SHIFT, 0u);
                }
                if (layout == BvhLayout::Wide) {  // one node, no lane used
                    ASSERT_EQ(bvh.wide_nodes.size(), 1u);
                    for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) EXPECT_EQ(wide_ref(bvh.wide_nodes[0], k), 0u);
                }
                Soup probe = random_soup(50, 3);
                for (const Ray& ray : random_rays(probe, 100, 4))
                    EXPECT_FALSE(hits_box(ray, node, std::numeric_limits<float>::infinity()));
            }
        }
    }
}

TEST(BvhBuild, EqualCentroidsAreSplitByIndex) {
    std::vector<Aabb> same(1000);
    for (auto& box : same) box.lower = glm::vec3(1.0f), box.upper = glm::vec3(2.0f);
    for (BvhMethod method : kMethods) {
        for (BvhLayout layout : kLayouts) {
            SCOPED_TRACE(describe(method, layout));
            Bvh bvh = build_bvh(same, options_for(method, layout));
            uint32_t depth = check_structure(bvh, same, 4);
            EXPECT_LE(depth, 10u) << "index medians keep it balanced";
        }
    }
}

// A thousand copies of the unit box, and options under which one leaf may hold them all: no split can pay, so only
// the layout's own cap on a leaf's primitives splits them.
std::vector<Aabb> unit_box_copies() {
    Aabb unit;
    unit.lower = glm::vec3(0.0f), unit.upper = glm::vec3(1.0f);
    return std::vector<Aabb>(1000, unit);
}

BvhBuildOptions one_leaf_options(BvhLayout layout) {
    BvhBuildOptions options = options_for(BvhMethod::BinnedSah, layout);
    options.max_leaf_size = 2000;
    return options;
}

TEST(BvhBuild, EscapeLayoutCapsLeavesAt255) {
    std::vector<Aabb> same = unit_box_copies();
    BvhBuildOptions options = one_leaf_options(BvhLayout::Escape);
    Bvh escape = build_bvh(same, options);
    check_structure(escape, same, 255);
    EXPECT_GT(escape.nodes.size(), 1u);
    options.layout = BvhLayout::Stack;
    Bvh stack = build_bvh(same, options);
    ASSERT_EQ(stack.nodes.size(), 1u) << "no split can pay when every box is the same";
    EXPECT_EQ(bits(stack.nodes[0].upper.w), 1000u);
}

// The wide collapse merges subtrees of up to wide_leaf_size primitives into one leaf (its blocks are tested
// together), and never beyond RT_WIDE_LEAF_MAX.
TEST(BvhBuild, WideLeavesMergeSmallSubtrees) {
    const Soup& soup = bunny();
    BvhBuildOptions options = options_for(BvhMethod::BinnedSah, BvhLayout::Wide);
    std::vector<size_t> node_counts;
    for (uint32_t merge : {1u, 4u, 8u, 64u}) {
        options.wide_leaf_size = merge;
        Bvh bvh = build_bvh(soup.bounds, options);
        uint32_t largest = 0;
        for (const BvhWideNode& node : bvh.wide_nodes)
            for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k)
                if (wide_ref(node, k) & RT_WIDE_LEAF) largest = std::max(largest, (wide_ref(node, k) & 7u) + 1);
        EXPECT_LE(largest, std::min(std::max(merge, 4u), RT_WIDE_LEAF_MAX)) << merge;
        if (merge >= 8) {
            EXPECT_EQ(largest, RT_WIDE_LEAF_MAX) << merge;
        }
        node_counts.push_back(bvh.wide_nodes.size());
        check_closest_hits(bvh, soup, 100);
    }
    EXPECT_EQ(node_counts[0], node_counts[1]) << "binary leaves hold at most 4: merging to 4 changes nothing";
    EXPECT_LT(node_counts[2], node_counts[1]) << "merging to 8 removes the nodes over two small leaves";
    EXPECT_EQ(node_counts[3], node_counts[2]) << "capped at RT_WIDE_LEAF_MAX";
}

TEST(BvhBuild, WideLayoutCapsLeavesAt8) {
    std::vector<Aabb> same = unit_box_copies();
    Bvh wide = build_bvh(same, one_leaf_options(BvhLayout::Wide));
    check_structure(wide, same, RT_WIDE_LEAF_MAX);
    EXPECT_GT(wide.wide_nodes.size(), 1u);
}

// A traversal holds at most (children - 1) entries per node on its path; the bound must cover the deepest path.
TEST(BvhBuild, WideStackBoundFollowsTheDeepestPath) {
    BvhWideNodes nodes(3, empty_wide_node());
    Aabb box{glm::vec3(0.0f), glm::vec3(1.0f)};
    for (uint32_t k = 0; k < 3; ++k) set_wide_lane_box(nodes[0], k, box);  // root: a leaf, node 1, node 2
    set_wide_lane_leaf(nodes[0], 0, 0, 1);
    set_wide_lane_node(nodes[0], 1, 1);
    set_wide_lane_node(nodes[0], 2, 2);
    for (uint32_t k = 0; k < 8; ++k) set_wide_lane_box(nodes[2], k, box), set_wide_lane_leaf(nodes[2], k, k, 1);
    set_wide_lane_box(nodes[1], 0, box);
    set_wide_lane_leaf(nodes[1], 0, 9, 1);
    EXPECT_EQ(wide_stack_bound(nodes, 1), 0u);
    EXPECT_EQ(wide_stack_bound(nodes, 2), 7u);
    EXPECT_EQ(wide_stack_bound(nodes, 0), 2u + 7u);
    EXPECT_THROW(set_wide_lane_leaf(nodes[1], 1, 0, RT_WIDE_LEAF_MAX + 1), Error);
    EXPECT_THROW(set_wide_lane_leaf(nodes[1], 1, RT_WIDE_FIRST_LIMIT, 1), Error);
}

TEST(BvhBuild, MedianSplitsAtTheBoxMiddleCyclingAxes) {
    Soup soup = random_soup(5000, 5);
    Bvh bvh = build_bvh(soup.bounds, options_for(BvhMethod::Median, BvhLayout::Stack));
    // Level 1 splits the root box on x, level 2 each child box on y: left primitives' centroids lie below the middle.
    std::vector<std::pair<uint32_t, int>> splits{{0, 0}};
    BvhNodeView root = decode_bvh_node(bvh, 0);
    ASSERT_FALSE(root.leaf);
    splits.push_back({root.left, 1});
    splits.push_back({root.right, 1});
    for (auto [index, axis] : splits) {
        BvhNodeView view = decode_bvh_node(bvh, index);
        ASSERT_FALSE(view.leaf);
        float middle = node_bounds(bvh.nodes[index]).center()[axis];
        auto check_side = [&](uint32_t child, bool below) {
            std::vector<uint32_t> stack{child};
            while (!stack.empty()) {
                BvhNodeView node = decode_bvh_node(bvh, stack.back());
                stack.pop_back();
                if (!node.leaf) {
                    stack.push_back(node.left);
                    stack.push_back(node.right);
                    continue;
                }
                for (uint32_t i = node.first; i < node.first + node.count; ++i)
                    EXPECT_EQ(soup.bounds[bvh.primitive_order[i]].center()[axis] < middle, below);
            }
        };
        check_side(view.left, true);
        check_side(view.right, false);
    }
}

TEST(BvhBuild, TopLevelOverInstancesWithOneInstancePerLeaf) {
    std::vector<Aabb> instances(7);
    for (int i = 0; i < 7; ++i)
        instances[i].lower = glm::vec3(3.0f * i, 0, 0), instances[i].upper = glm::vec3(3.0f * i + 1, 1, 1);
    for (BvhLayout layout : kLayouts) {
        BvhBuildOptions options = options_for(BvhMethod::BinnedSah, layout);
        options.max_leaf_size = 1;
        options.wide_leaf_size = 1;  // as the device scene's top level builds it
        Bvh bvh = build_bvh(instances, options);
        EXPECT_EQ(bvh.nodes.size(), 13u);
        check_structure(bvh, instances, 1);
    }
}

TEST(BvhBuild, SahCostOfATwoLeafTree) {
    std::vector<Aabb> boxes(2);
    boxes[0].lower = glm::vec3(0.0f), boxes[0].upper = glm::vec3(1.0f);
    boxes[1].lower = glm::vec3(2.0f, 0, 0), boxes[1].upper = glm::vec3(3.0f, 1, 1);
    BvhBuildOptions options;
    options.max_leaf_size = 1;
    Bvh bvh = build_bvh(boxes, options);
    ASSERT_EQ(bvh.nodes.size(), 3u);
    // root half-area 3 + 1 + 3 = 7, each leaf 3: (1 * 7 + 1 * (3 + 3)) / 7
    EXPECT_FLOAT_EQ(bvh.sah_cost, 13.0f / 7.0f);
    options.traversal_cost = 2.0f;
    EXPECT_FLOAT_EQ(sah_cost(bvh, options), 20.0f / 7.0f);
}

TEST(BvhBuild, RejectsInvalidOptions) {
    std::vector<Aabb> boxes(3, Aabb{glm::vec3(0.0f), glm::vec3(1.0f)});
    BvhBuildOptions options;
    options.max_leaf_size = 0;
    EXPECT_THROW(build_bvh(boxes, options), Error);
    options = {};
    options.bins = 1;
    EXPECT_THROW(build_bvh(boxes, options), Error);
}

// Moves every triangle (some become degenerate), refits, and expects the structure and closest hits of a fresh
// build: same primitives, every box still holding its children, the same root box as a rebuild.
TEST(BvhRefit, MovedPrimitivesKeepInvariantsAndHits) {
    Soup soup = random_soup(20000, 6);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> offset(-2.0f, 2.0f);
    std::vector<Triangle> moved = soup.triangles;
    for (size_t i = 0; i < moved.size(); ++i) {
        glm::vec3 shift(offset(rng), offset(rng), offset(rng));
        moved[i] = {moved[i].a + shift, moved[i].b + shift, moved[i].c + shift};
        if (i % 23 == 0 && usable(soup.bounds[i])) moved[i].b = moved[i].c = moved[i].a;
    }
    Soup after = make_soup(moved);
    for (BvhMethod method : kMethods) {
        for (BvhLayout layout : kLayouts) {
            SCOPED_TRACE(describe(method, layout));
            Bvh bvh = build_bvh(soup.bounds, options_for(method, layout));
            Bvh unchanged = bvh;
            refit_bvh(unchanged, soup.bounds);
            EXPECT_TRUE(same_bytes(unchanged.nodes, bvh.nodes)) << "refit with the same bounds is the identity";
            EXPECT_TRUE(same_bytes(unchanged.wide_nodes, bvh.wide_nodes)) << "also for wide nodes";

            float cost_before = bvh.sah_cost;
            refit_bvh(bvh, after.bounds);
            EXPECT_NE(bvh.sah_cost, cost_before);
            // Refit keeps the newly degenerate primitives in their leaves (their empty bounds add nothing).
            std::vector<bool> built_over;
            for (const auto& box : soup.bounds) built_over.push_back(usable(box));
            check_structure(bvh, after.bounds, 4, built_over);
            check_closest_hits(bvh, after, 300);

            Bvh rebuilt = build_bvh(after.bounds, options_for(method, layout));
            EXPECT_TRUE(contains(box_of(bvh.nodes[0]), box_of(rebuilt.nodes[0])) &&
                        contains(box_of(rebuilt.nodes[0]), box_of(bvh.nodes[0])))
                << "refit and rebuild cover the same space";
        }
    }
    Bvh bvh = build_bvh(soup.bounds, BvhBuildOptions{});
    std::vector<Aabb> too_few(soup.bounds.begin(), soup.bounds.end() - 1);
    EXPECT_THROW(refit_bvh(bvh, too_few), Error);
}

}  // namespace
}  // namespace prism
