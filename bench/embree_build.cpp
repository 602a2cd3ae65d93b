#include "bench/embree_build.h"

#include <chrono>
#include <cstring>
#include <string>

#include <embree3/rtcore.h>

#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism::oracle {

namespace {

RTCBuildQuality to_rtc(EmbreeQuality quality) {
    switch (quality) {
        case EmbreeQuality::Low: return RTC_BUILD_QUALITY_LOW;
        case EmbreeQuality::Medium: return RTC_BUILD_QUALITY_MEDIUM;
        case EmbreeQuality::High: return RTC_BUILD_QUALITY_HIGH;
    }
    return RTC_BUILD_QUALITY_MEDIUM;
}

constexpr uint32_t kMaxLeaf = 8;

// What Embree's callbacks make: nodes in its thread-local allocator, freed with the RTCBVH.
struct EmbreeNode {
    bool leaf = false;
    EmbreeNode* children[2] = {nullptr, nullptr};
    Aabb child_boxes[2];
    uint32_t count = 0;  // leaf
    uint32_t primitives[kMaxLeaf];
};

void* create_node(RTCThreadLocalAllocator allocator, unsigned child_count, void*) {
    if (child_count != 2) return nullptr;  // branching factor 2 asked for
    return new (rtcThreadLocalAlloc(allocator, sizeof(EmbreeNode), alignof(EmbreeNode))) EmbreeNode{};
}

void set_node_children(void* node, void** children, unsigned child_count, void*) {
    for (unsigned k = 0; k < child_count && k < 2; ++k)
        static_cast<EmbreeNode*>(node)->children[k] = static_cast<EmbreeNode*>(children[k]);
}

void set_node_bounds(void* node, const RTCBounds** bounds, unsigned child_count, void*) {
    for (unsigned k = 0; k < child_count && k < 2; ++k) {
        Aabb& box = static_cast<EmbreeNode*>(node)->child_boxes[k];
        box.lower = {bounds[k]->lower_x, bounds[k]->lower_y, bounds[k]->lower_z};
        box.upper = {bounds[k]->upper_x, bounds[k]->upper_y, bounds[k]->upper_z};
    }
}

void* create_leaf(RTCThreadLocalAllocator allocator, const RTCBuildPrimitive* primitives, size_t count, void*) {
    auto* node = new (rtcThreadLocalAlloc(allocator, sizeof(EmbreeNode), alignof(EmbreeNode))) EmbreeNode{};
    node->leaf = true;
    node->count = uint32_t(std::min<size_t>(count, kMaxLeaf));
    for (uint32_t i = 0; i < node->count; ++i) node->primitives[i] = primitives[i].primID;
    return node;
}

// Embree's tree as Prism's intermediate tree, so bvh_flatten.cpp lays it out exactly as it lays out Prism's own.
const BvhBuildNode* to_build_node(const EmbreeNode& node, const Aabb& box, uint32_t depth, BvhTree& tree) {
    BvhBuildNode& out = tree.arenas.back().emplace_back();
    out.box = box;
    tree.node_count += 1;
    tree.depth = std::max(tree.depth, depth);
    if (node.leaf) {
        out.first = uint32_t(tree.primitive_order.size());
        out.count = node.count;
        tree.primitive_order.insert(tree.primitive_order.end(), node.primitives, node.primitives + node.count);
        return &out;
    }
    for (uint32_t k = 0; k < 2; ++k) {
        out.children[k] = to_build_node(*node.children[k], node.child_boxes[k], depth + 1, tree);
        out.nodes += out.children[k]->nodes;
    }
    return &out;
}

}  // namespace

const char* embree_quality_name(EmbreeQuality quality) {
    switch (quality) {
        case EmbreeQuality::Low: return "low";
        case EmbreeQuality::Medium: return "medium";
        case EmbreeQuality::High: return "high";
    }
    return "?";
}

const char* embree_version() { return RTC_VERSION_STRING; }

EmbreeBuilder::EmbreeBuilder(unsigned threads) {
    std::string config = threads ? "threads=" + std::to_string(threads) : "";
    device_ = rtcNewDevice(config.c_str());
    if (!device_) throw Error("embree: cannot create a device");
}

EmbreeBuilder::~EmbreeBuilder() { rtcReleaseDevice(static_cast<RTCDevice>(device_)); }

double EmbreeBuilder::commit_ms(const TriangleSoupView& mesh, EmbreeQuality quality) const {
    auto device = static_cast<RTCDevice>(device_);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, to_rtc(quality));
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, to_rtc(quality));
    // New (padded) buffers: a shared one would have to be readable 16 bytes past its last vertex.
    void* vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3),
                                             mesh.positions.size());
    std::memcpy(vertices, mesh.positions.data(), mesh.positions.size_bytes());
    void* indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(glm::uvec3),
                                            mesh.triangles.size());
    std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size_bytes());
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    auto start = std::chrono::steady_clock::now();
    rtcCommitScene(scene);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    rtcReleaseScene(scene);
    return ms;
}

Bvh EmbreeBuilder::build_binary(std::span<const Aabb> bounds, EmbreeQuality quality, uint32_t max_leaf_size,
                                uint32_t sah_block_size) const {
    if (max_leaf_size == 0 || max_leaf_size > kMaxLeaf) throw Error("embree build: leaves hold 1 to 8 primitives");
    std::vector<RTCBuildPrimitive> primitives;
    primitives.reserve(bounds.size());
    Aabb root_box;
    for (uint32_t i = 0; i < bounds.size(); ++i) {
        const Aabb& box = bounds[i];
        if (!bvh_usable_bounds(box)) continue;
        root_box.grow(box);
        primitives.push_back(
            RTCBuildPrimitive{box.lower.x, box.lower.y, box.lower.z, 0, box.upper.x, box.upper.y, box.upper.z, i});
    }
    RTCBVH handle = rtcNewBVH(static_cast<RTCDevice>(device_));
    RTCBuildArguments arguments = rtcDefaultBuildArguments();
    arguments.buildQuality = to_rtc(quality);
    arguments.maxBranchingFactor = 2;
    arguments.maxDepth = 1024;
    arguments.sahBlockSize = sah_block_size;
    arguments.minLeafSize = 1;
    arguments.maxLeafSize = max_leaf_size;
    arguments.traversalCost = 1.0f;
    arguments.intersectionCost = 1.0f;
    arguments.bvh = handle;
    arguments.primitives = primitives.data();
    arguments.primitiveCount = primitives.size();
    arguments.primitiveArrayCapacity = primitives.size();
    arguments.createNode = create_node;
    arguments.setNodeChildren = set_node_children;
    arguments.setNodeBounds = set_node_bounds;
    arguments.createLeaf = create_leaf;
    auto start = std::chrono::steady_clock::now();
    auto* root = static_cast<EmbreeNode*>(rtcBuildBVH(&arguments));
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!root) {
        rtcReleaseBVH(handle);
        throw Error("embree: rtcBuildBVH failed");
    }
    BvhTree tree;
    tree.arenas.emplace_back();
    tree.root = to_build_node(*root, root_box, 1, tree);
    rtcReleaseBVH(handle);
    Bvh bvh;
    bvh.nodes = flatten_bvh_tree(tree, BvhLayout::Stack);
    bvh.primitive_order = std::move(tree.primitive_order);
    bvh.depth = tree.depth;
    bvh.layout = BvhLayout::Stack;
    bvh.options.max_leaf_size = max_leaf_size;
    bvh.primitive_count = uint32_t(bounds.size());
    bvh.build_ms = ms;
    bvh.sah_cost = sah_cost(bvh, bvh.options);
    return bvh;
}

}  // namespace prism::oracle
