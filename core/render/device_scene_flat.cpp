// The wide layout with its instances flattened: one world-space BVH over every instance's triangles, in place of a
// top level over instances whose leaves enter each mesh's BVH in object space. A static scene (a model on a floor,
// as Embree's oracle builds it) then pays no top-level node, no instance entry and no ray transform per ray: the
// cpu backend's bunny scene traced diffuse rays 12% faster, primary rays 15% (docs/kernels.md). The cost: a mesh
// instanced n times is stored n times, and moving an instance means rebuilding everything, so a viewer whose
// objects may move keeps the two-level layout (BvhBuildOptions::flatten_instances off).
//
// Hits report what the two-level layout reports: the instance, the primitive within its mesh and its slot in
// `triangles` (object space, where shading rebuilds the geometric normal). Only the intersection arithmetic runs in
// world space, so t, u and v can differ from the two-level layout's in the last bits.
#include "core/render/device_scene_flat.h"

#include <bit>

#include "core/util/error.h"

namespace prism {
namespace {

// World-space triangles of every instance, as the builder and the leaf blocks see them.
struct WorldTriangle {
    glm::vec3 a, b, c;
    uint32_t instance, primitive, slot;
};

auto& lane(auto& v, uint32_t k) { return k == 0 ? v.x : k == 1 ? v.y : k == 2 ? v.z : v.w; }

}  // namespace

void build_flat_instances(DeviceScene& device, const Scene& scene, const std::vector<uint32_t>& first_triangle,
                          const std::vector<uint32_t>& triangle_count, const BvhProgress& progress) {
    std::vector<WorldTriangle> triangles;
    size_t triangle_total = 0;
    for (const prism::Instance& instance : scene.instances) triangle_total += triangle_count[instance.mesh];
    triangles.reserve(triangle_total);
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const prism::Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes[instance.mesh];
        uint32_t first = first_triangle[instance.mesh];
        for (uint32_t slot = first; slot < first + triangle_count[instance.mesh]; ++slot) {
            // Transformed as the Embree oracle transforms its flattened copy (bench/embree_oracle.cpp).
            uint32_t primitive = std::bit_cast<uint32_t>(device.triangles[slot].v0.w);
            glm::uvec3 tri = mesh.triangles[primitive];
            auto world = [&](uint32_t v) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f)); };
            triangles.push_back(WorldTriangle{world(tri.x), world(tri.y), world(tri.z), i, primitive, slot});
        }
    }
    std::vector<Aabb> bounds(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
        bounds[t].grow(triangles[t].a);
        bounds[t].grow(triangles[t].b);
        bounds[t].grow(triangles[t].c);
    }
    BvhBuildOptions options = device.bvh_options;
    // A floor plane around a model stretches the centroid range the binning divides: with 16 bins the dragon
    // scene's model fell into one or two bins at the top of the tree and its diffuse rays tested a third more
    // triangles. 32 bins (as Embree bins) gave the two-level layout's leaf tests back.
    options.bins = std::max(options.bins, 32u);
    Bvh bvh = build_bvh(bounds, options, progress);

    // Leaves become blocks of four world-space triangles; each lane remembers its instance, primitive and slot.
    device.triangle_blocks.clear();
    // Leaves hold 1 to 8 triangles, mostly 3 to 8: about one block per two triangles (a hint; it may still grow).
    device.triangle_blocks.reserve(triangles.size() / 2 + 1);
    device.wide_nodes = std::move(bvh.wide_nodes);
    for (BvhWideNode& node : device.wide_nodes)
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            if (!wide_lane_leaf(node, k)) continue;
            uint32_t first = wide_lane_first(node, k), count = wide_lane_count(node, k);
            uint32_t first_block = uint32_t(device.triangle_blocks.size());
            for (uint32_t i = 0; i < count; i += 4) {
                TriangleBlock block{};  // unused lanes: zero edges, never hit
                block.slot = block.primitive = block.instance = uint4{~0u, ~0u, ~0u, ~0u};
                for (uint32_t l = 0; l < 4 && i + l < count; ++l) {
                    const WorldTriangle& t = triangles[bvh.primitive_order[first + i + l]];
                    glm::vec3 e1 = t.b - t.a, e2 = t.c - t.a;
                    lane(block.v0x, l) = t.a.x, lane(block.v0y, l) = t.a.y, lane(block.v0z, l) = t.a.z;
                    lane(block.e1x, l) = e1.x, lane(block.e1y, l) = e1.y, lane(block.e1z, l) = e1.z;
                    lane(block.e2x, l) = e2.x, lane(block.e2y, l) = e2.y, lane(block.e2z, l) = e2.z;
                    lane(block.slot, l) = t.slot;
                    lane(block.primitive, l) = t.primitive;
                    lane(block.instance, l) = t.instance;
                }
                device.triangle_blocks.push_back(block);
            }
            set_wide_lane_leaf(node, k, first_block, count);
        }
    uint32_t bound = wide_stack_bound(device.wide_nodes, 0);
    if (bound > RT_BVH_WIDE_STACK_SIZE)
        throw Error(scene.source + ": the flattened wide BVH needs " + std::to_string(bound) +
                    " traversal stack entries, more than " + std::to_string(RT_BVH_WIDE_STACK_SIZE) +
                    " (use the stack layout)");
    device.top_level_nodes = 0;  // no top level: moving an instance cannot refit anything
    device.sah_cost = bvh.sah_cost;
}

}  // namespace prism
