#include "core/render/device_scene.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <optional>
#include <utility>

#include "core/bvh/bvh_tree.h"
#include "core/render/device_scene_flat.h"
#include "core/scene/closed_solid.h"
#include "core/util/error.h"
#include "kernels/intersect.h"
#include "kernels/math.h"

namespace prism {
namespace {

float4 to_float4(glm::vec3 v, float w) { return float4{v.x, v.y, v.z, w}; }
float4 to_float4(glm::vec4 v) { return float4{v.x, v.y, v.z, v.w}; }
float as_float(uint32_t u) { return std::bit_cast<float>(u); }
uint32_t as_uint(float f) { return std::bit_cast<uint32_t>(f); }

// A triangle that no ray can hit reliably (zero area or non-finite) is left out of its BVH; it keeps its index.
bool degenerate(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    glm::vec3 n = glm::cross(b - a, c - a);
    float area2 = glm::dot(n, n);
    return !(area2 > 0.0f) || !std::isfinite(area2);
}

// Mesh triangle t as the traversal tests it: v0 with the primitive index in w, the edges with rt_edge_scale in w.
TriangleGeometry triangle_geometry(const std::vector<glm::vec3>& positions, glm::uvec3 tri, uint32_t t) {
    glm::vec3 a = positions[tri.x], b = positions[tri.y], c = positions[tri.z];
    glm::vec3 e1 = b - a, e2 = c - a;
    float edge_scale = rt_edge_scale(float3{e1.x, e1.y, e1.z}, float3{e2.x, e2.y, e2.z});
    return TriangleGeometry{float4{a.x, a.y, a.z, std::bit_cast<float>(t)}, float4{e1.x, e1.y, e1.z, edge_scale},
                            float4{e2.x, e2.y, e2.z, 0.0f}};
}

Aabb triangle_bounds(const std::vector<glm::vec3>& positions, glm::uvec3 tri) {
    Aabb box;
    box.grow(positions[tri.x]);
    box.grow(positions[tri.y]);
    box.grow(positions[tri.z]);
    return box;
}

// Node indices of a separately built BVH moved to where it lands in the shared arrays.
void rebase_nodes(BvhNodes& nodes, BvhLayout layout, uint32_t node_offset, uint32_t primitive_offset) {
    for (BvhNode& node : nodes) {
        uint32_t lower_w = as_uint(node.lower.w);
        uint32_t upper_w = as_uint(node.upper.w);
        if (layout != BvhLayout::Escape) {
            bool leaf = upper_w != 0;
            node.lower.w = as_float(lower_w + (leaf ? primitive_offset : node_offset));
        } else {
            node.lower.w = as_float(lower_w + node_offset);
            if (upper_w != RT_ESCAPE_INTERIOR) {
                uint32_t first = (upper_w & RT_ESCAPE_FIRST_MASK) + primitive_offset;
                if (first > RT_ESCAPE_FIRST_MASK)
                    throw Error(
                        "scene: more than 16,777,215 triangles do not fit the escape BVH layout "
                        "(use the stack layout)");
                node.upper.w = as_float((upper_w & ~RT_ESCAPE_FIRST_MASK) | first);
            }
        }
    }
}

// Top-level leaves index `primitive_order`; the kernels want the instance index itself. The builder's tree is
// kept unchanged for refits; this returns the nodes the device sees.
BvhNodes top_level_device_nodes(const Bvh& bvh) {
    BvhNodes nodes = bvh.nodes;
    for (BvhNode& node : nodes) {
        uint32_t upper_w = as_uint(node.upper.w);
        if (bvh.layout != BvhLayout::Escape) {
            if (upper_w == 0) continue;
            if (upper_w != 1) throw Error("internal: top-level BVH leaf with more than one instance");
            node.lower.w = as_float(bvh.primitive_order[as_uint(node.lower.w)]);
        } else {
            if (upper_w == RT_ESCAPE_INTERIOR) continue;
            if ((upper_w >> RT_ESCAPE_COUNT_SHIFT) != 1)
                throw Error("internal: top-level BVH leaf with more than one instance");
            uint32_t instance = bvh.primitive_order[upper_w & RT_ESCAPE_FIRST_MASK];
            node.upper.w = as_float((1u << RT_ESCAPE_COUNT_SHIFT) | instance);
        }
    }
    return nodes;
}

// Wide nodes of a separately built mesh BVH moved to where they land in `wide_nodes`.
void rebase_wide_nodes(BvhWideNodes& nodes, uint32_t node_offset, uint32_t primitive_offset) {
    for (BvhWideNode& node : nodes)
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            if (!wide_lane_used(node, k)) continue;
            if (wide_lane_leaf(node, k))
                set_wide_lane_leaf(node, k, wide_lane_first(node, k) + primitive_offset, wide_lane_count(node, k));
            else
                set_wide_lane_node(node, k, wide_lane_ref(node, k) + node_offset);
        }
}

// A mesh's wide leaves moved from triangle ranges (slots in `triangles`) to blocks of four appended to `blocks`.
void block_wide_leaves(BvhWideNodes& nodes, const UninitializedVector<TriangleGeometry>& triangles,
                       UninitializedVector<TriangleBlock>& blocks) {
    auto lane = [](auto& v, uint32_t k) -> auto& { return k == 0 ? v.x : k == 1 ? v.y : k == 2 ? v.z : v.w; };
    for (BvhWideNode& node : nodes)
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            if (!wide_lane_leaf(node, k)) continue;
            uint32_t first = wide_lane_first(node, k), count = wide_lane_count(node, k);
            uint32_t first_block = uint32_t(blocks.size());
            for (uint32_t i = 0; i < count; i += 4) {
                TriangleBlock block{};  // unused lanes: zero edges, never hit
                block.slot = block.primitive = block.instance = uint4{~0u, ~0u, ~0u, ~0u};
                for (uint32_t l = 0; l < 4 && i + l < count; ++l) {
                    const TriangleGeometry& t = triangles[first + i + l];
                    lane(block.v0x, l) = t.v0.x, lane(block.v0y, l) = t.v0.y, lane(block.v0z, l) = t.v0.z;
                    lane(block.e1x, l) = t.e1.x, lane(block.e1y, l) = t.e1.y, lane(block.e1z, l) = t.e1.z;
                    lane(block.e2x, l) = t.e2.x, lane(block.e2y, l) = t.e2.y, lane(block.e2z, l) = t.e2.z;
                    lane(block.slot, l) = first + i + l;
                    lane(block.primitive, l) = std::bit_cast<uint32_t>(t.v0.w);
                }
                blocks.push_back(block);
            }
            set_wide_lane_leaf(node, k, first_block, count);
        }
}

// The top level in the wide layout: leaves name the instance itself, and the nodes are padded to `capacity` (the
// most any top level over these instances can need), so a rebuild never moves the mesh BVHs behind it.
BvhWideNodes top_level_wide_device_nodes(const Bvh& bvh, size_t capacity) {
    BvhWideNodes nodes = bvh.wide_nodes;
    if (nodes.size() > capacity) throw Error("internal: wide top level larger than its capacity");
    for (BvhWideNode& node : nodes)
        for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k) {
            if (!wide_lane_leaf(node, k)) continue;
            if (wide_lane_count(node, k) != 1) throw Error("internal: top-level BVH leaf with more than one instance");
            set_wide_lane_leaf(node, k, bvh.primitive_order[wide_lane_first(node, k)], 1);
        }
    nodes.resize(capacity, empty_wide_node());
    return nodes;
}

// A 4-ary tree over n leaves, each node with at least two children (or one node for n = 1), has at most n - 1.
size_t wide_top_level_capacity(size_t instances) { return instances > 1 ? instances - 1 : 1; }

Aabb transformed_bounds(const Aabb& box, const glm::mat4& m) {
    Aabb out;
    for (int corner = 0; corner < 8; ++corner) {
        glm::vec3 p{(corner & 1) ? box.upper.x : box.lower.x, (corner & 2) ? box.upper.y : box.lower.y,
                    (corner & 4) ? box.upper.z : box.lower.z};
        out.grow(glm::vec3(m * glm::vec4(p, 1.0f)));
    }
    return out;
}

// `solid`: the mesh's object-space bounds when the instance is a closed solid (RT_INSTANCE_CLOSED_SOLID), else null.
::Instance device_instance(const glm::mat4& transform, uint32_t root, uint32_t first_triangle, uint32_t first_shading,
                           const Aabb* solid) {
    glm::mat4 inverse = glm::inverse(transform);
    ::Instance out{};
    // glm is column-major: row r of the 3x4 matrix is (m[0][r], m[1][r], m[2][r], m[3][r]).
    auto row = [](const glm::mat4& m, int r) { return float4{m[0][r], m[1][r], m[2][r], m[3][r]}; };
    out.world_to_object0 = row(inverse, 0);
    out.world_to_object1 = row(inverse, 1);
    out.world_to_object2 = row(inverse, 2);
    out.object_to_world0 = row(transform, 0);
    out.object_to_world1 = row(transform, 1);
    out.object_to_world2 = row(transform, 2);
    bool identity = inverse == glm::mat4(1.0f);
    out.root = root;
    out.first_triangle = first_triangle;
    out.first_shading = first_shading;
    out.flags = (glm::determinant(glm::mat3(transform)) < 0.0f ? RT_INSTANCE_MIRRORED : 0u) |
                (identity ? RT_INSTANCE_IDENTITY : 0u) | (solid ? RT_INSTANCE_CLOSED_SOLID : 0u);
    if (solid) {
        out.solid_lower = to_float4(solid->lower, 0.0f);
        out.solid_upper = to_float4(solid->upper, 0.0f);
    }
    return out;
}

// A light as the shade stage reads it (kernels/types.h, Light). The spot's two numbers are glTF's reference code's
// (KHR_lights_punctual): a cone whose angles are equal gets a hard edge, not a division by zero.
::Light device_light(const Light& light) {
    ::Light out{};
    out.color = to_float4(light.color * light.intensity, light.range > 0.0f ? 1.0f / light.range : 0.0f);
    out.cone = float4{0.0f, 0.0f, 0.0f, 1.0f};
    if (light.type == LightType::Directional) {
        out.position = to_float4(glm::normalize(light.direction), RT_LIGHT_DIRECTIONAL_CODE);
    } else if (light.type == LightType::Spot) {
        out.position = to_float4(light.position, RT_LIGHT_SPOT_CODE);
        float cos_outer = std::cos(light.outer_cone);
        float scale = 1.0f / std::max(0.001f, std::cos(light.inner_cone) - cos_outer);
        out.cone = to_float4(glm::normalize(light.direction) * scale, -cos_outer * scale);
    } else {
        out.position = to_float4(light.position, RT_LIGHT_POINT_CODE);
    }
    return out;
}

void build_top_level(DeviceScene& device, const std::vector<glm::mat4>& transforms, bool rebuild) {
    std::vector<Aabb> bounds(transforms.size());
    for (size_t i = 0; i < transforms.size(); ++i)
        bounds[i] = transformed_bounds(device.mesh_bounds[device.instance_meshes[i]], transforms[i]);
    if (rebuild) {
        BvhBuildOptions options = device.bvh_options;
        options.max_leaf_size = 1;
        options.wide_leaf_size = 1;  // a top-level leaf is one instance
        device.top_level = build_bvh(bounds, options);
    } else {
        // refit_bvh maps leaves through primitive_order, which still holds the instance order.
        refit_bvh(device.top_level, bounds);
    }
}

::Material device_material(const prism::Material& m, uint32_t first_layer) {
    ::Material out{};
    out.diffuse = to_float4(m.diffuse, m.use_vertex_colors ? 1.0f : 0.0f);
    out.specular = to_float4(m.specular, m.reflectivity);
    out.ambient = to_float4(m.ambient, m.transmittance);
    out.fresnel = float4{m.fresnel_bias, m.fresnel_scale, m.fresnel_power, m.thickness};
    out.ior = to_float4(m.ior, 0.0f);
    out.emissive = to_float4(m.emissive, 0.0f);
    out.first_layer = first_layer;
    out.layer_count = static_cast<uint32_t>(m.textures.size());
    out.flags = (m.metal_rough ? RT_MATERIAL_METAL_ROUGH : 0u) |
                (m.alpha_mode == AlphaMode::Mask ? RT_MATERIAL_ALPHA_MASK : 0u) |
                (m.alpha_mode == AlphaMode::Blend ? RT_MATERIAL_ALPHA_BLEND : 0u) |
                (m.vertex_colors_replace ? RT_MATERIAL_VERTEX_REPLACE : 0u) |
                (m.double_sided ? 0u : RT_MATERIAL_SINGLE_SIDED);
    out.alpha = m.alpha;
    out.emissive.w = m.alpha_cutoff;
    out.absorption = to_float4(m.absorption, 0.0f);
    out.metallic = m.metallic;
    out.roughness = m.roughness;
    out.occlusion_strength = m.occlusion_strength;
    out.normal_scale = m.normal_scale;
    // The maps' layers follow the stack's, in this order (see material_maps).
    uint32_t next = first_layer + static_cast<uint32_t>(m.textures.size());
    auto map_index = [&next](const std::optional<prism::TextureLayer>& map) { return map ? next++ : RT_NONE; };
    out.metal_rough_map = map_index(m.metal_rough_map);
    out.emissive_map = map_index(m.emissive_map);
    out.occlusion_map = map_index(m.occlusion_map);
    out.normal_map = map_index(m.normal_map);
    out.specular_map = map_index(m.specular_map);
    out.specular_color_map = map_index(m.specular_color_map);
    out.iridescence_map = map_index(m.iridescence_map);
    out.iridescence_thickness_map = map_index(m.iridescence_thickness_map);
    out.iridescence =
        float4{m.iridescence, m.iridescence_ior, m.iridescence_thickness_min, m.iridescence_thickness_max};
    out.clearcoat_map = map_index(m.clearcoat_map);
    out.clearcoat_roughness_map = map_index(m.clearcoat_roughness_map);
    out.clearcoat = float4{m.clearcoat, m.clearcoat_roughness, 0.0f, 0.0f};
    out.unused0 = out.unused1 = RT_NONE;
    return out;
}

// A material's texture stack, then its single-purpose maps in device_material's order.
std::vector<prism::TextureLayer> material_layers(const prism::Material& m) {
    std::vector<prism::TextureLayer> layers = m.textures;
    for (const auto* map :
         {&m.metal_rough_map, &m.emissive_map, &m.occlusion_map, &m.normal_map, &m.specular_map, &m.specular_color_map,
          &m.iridescence_map, &m.iridescence_thickness_map, &m.clearcoat_map, &m.clearcoat_roughness_map})
        if (*map) layers.push_back(**map);
    return layers;
}

}  // namespace

size_t DeviceScene::byte_size() const {
    size_t bytes = 0;
#define RT_DATA_ARRAY(slot, type, name, access, role) PRISM_IF_SCENE_ARRAY(role, bytes += name.size() * sizeof(::type);)
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    return bytes;
}

// Which meshes an animation poses anew (Scene::animation.deformations).
static std::vector<bool> deformed_meshes(const Scene& scene) {
    std::vector<bool> deformed(scene.meshes.size(), false);
    for (const MeshDeformation& deformation : scene.animation.deformations)
        if (deformation.mesh < deformed.size()) deformed[deformation.mesh] = true;
    return deformed;
}

// Which instances are closed solids (RT_INSTANCE_CLOSED_SOLID): the mesh bounds a solid (is_closed_solid), some
// material of the instance lets rays in (transmittance; a ray in an opaque solid is lost anyway), every one stops
// shadow rays (alpha OPAQUE: cut-out and blended surfaces let light through in the shadow_layers stage), and no
// animation poses the mesh anew (its bounds would move from under the flag). Each mesh is examined at most once,
// and only when some instance of it could use the answer.
static std::vector<bool> closed_solid_instances(const Scene& scene) {
    const std::vector<bool> deformed = deformed_meshes(scene);
    // What a set of materials allows: rays in (some transmittance) and shadow rays through (some not alpha-opaque).
    struct Materials {
        bool enterable = false, opaque = true;
        void add(const Scene& scene, uint32_t index) {
            const Material fallback{};
            const Material& m = index < scene.materials.size() ? scene.materials[index] : fallback;
            enterable = enterable || m.transmittance > 0.0f;
            opaque = opaque && m.alpha_mode == AlphaMode::Opaque;
        }
    };
    // Per mesh, once (a forest instancing one tree a thousand times reads its triangles' materials once).
    std::vector<std::optional<Materials>> mesh_materials(scene.meshes.size());
    auto own_materials = [&](uint32_t m) {
        if (!mesh_materials[m]) {
            Materials found;
            std::vector<bool> seen(scene.materials.size() + 1, false);
            if (scene.meshes[m].triangle_materials.empty()) found.add(scene, 0u);
            for (uint32_t index : scene.meshes[m].triangle_materials) {
                uint32_t slot = std::min<uint32_t>(index, uint32_t(scene.materials.size()));
                if (!seen[slot]) found.add(scene, index), seen[slot] = true;
            }
            mesh_materials[m] = found;
        }
        return *mesh_materials[m];
    };
    enum class Closed : uint8_t { Unknown, Yes, No };
    std::vector<Closed> closed(scene.meshes.size(), Closed::Unknown);
    std::vector<bool> solid(scene.instances.size(), false);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        if (instance.mesh >= scene.meshes.size() || deformed[instance.mesh]) continue;
        Materials materials;
        if (instance.material_override != kNoMaterialOverride)
            materials.add(scene, instance.material_override);
        else
            materials = own_materials(instance.mesh);
        if (!materials.enterable || !materials.opaque) continue;
        if (closed[instance.mesh] == Closed::Unknown)
            closed[instance.mesh] = is_closed_solid(scene.meshes[instance.mesh]) ? Closed::Yes : Closed::No;
        solid[i] = closed[instance.mesh] == Closed::Yes;
    }
    return solid;
}

// Flattening stores a mesh once per instance: a scene that instances its meshes heavily (a forest of one tree)
// would multiply its memory, so it keeps the two-level layout when the flattened triangles would exceed
// `growth_limit` times the meshes' own.
static bool flattening_fits(const Scene& scene, float growth_limit) {
    double own = 0.0, flattened = 0.0;
    for (const Mesh& mesh : scene.meshes) own += double(mesh.triangles.size());
    for (const Instance& instance : scene.instances) flattened += double(scene.meshes[instance.mesh].triangles.size());
    return flattened <= double(growth_limit) * std::max(own, 1.0);
}

DeviceScene build_device_scene(const Scene& scene, const BvhBuildOptions& options, const BvhProgress& progress) {
    auto start = std::chrono::steady_clock::now();
    DeviceScene device;
    device.bvh_options = options;
    // The closed-solid analysis reads only the scene: it runs beside the BVH builds, which leave cores idle in their
    // serial steps.
    // It returns its answer and its time; nothing of `device` is written from its thread.
    std::future<std::pair<std::vector<bool>, double>> closed_solids =
        std::async(std::launch::async, [&scene, &options] {
            auto solids_start = std::chrono::steady_clock::now();
            std::vector<bool> solid(scene.instances.size(), false);
            if (options.closed_solids) solid = closed_solid_instances(scene);
            return std::pair(
                std::move(solid),
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - solids_start).count());
        });

    // Mesh BVHs, built separately then placed after the top level.
    struct MeshPlacement {
        uint32_t first_vertex, first_shading, first_triangle;
        Bvh bvh;
    };
    std::vector<MeshPlacement> placements;
    placements.reserve(scene.meshes.size());
    double triangle_weighted_sah = 0.0;
    size_t bvh_triangles = 0;
    // Flattened instances trace one world BVH (core/render/device_scene_flat.cpp): no mesh needs a BVH of its own, its
    // triangles keep their file order (degenerate ones left out).
    bool flatten = options.layout == BvhLayout::Wide && options.flatten_instances &&
                   flattening_fits(scene, options.flatten_growth_limit);
    device.bvh_options.flatten_instances = flatten;  // what was built: the renderer's frame flag reads it
    device.mesh_bounds.resize(scene.meshes.size());
    // The meshes' builds report their share of every triangle the scene's BVHs will hold.
    double triangles_to_place = 0.0, triangles_placed = 0.0;
    size_t vertex_total = 0, triangle_total = 0;
    for (const Mesh& mesh : scene.meshes) {
        triangles_to_place += double(mesh.triangles.size());
        vertex_total += mesh.positions.size();
        triangle_total += mesh.triangles.size();
    }
    // Reserved: grown one element at a time, a million-triangle mesh would copy these arrays over and over.
    device.vertices.reserve(vertex_total);
    device.triangle_shading.reserve(triangle_total);
    device.triangles.reserve(triangle_total);
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        MeshPlacement placement{static_cast<uint32_t>(device.vertices.size()),
                                static_cast<uint32_t>(device.triangle_shading.size()),
                                static_cast<uint32_t>(device.triangles.size()),
                                {}};
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            Vertex vertex{};
            float vertex_flags = static_cast<float>((mesh.normals.empty() ? 0u : RT_VERTEX_HAS_NORMAL) |
                                                    (mesh.colors.empty() ? 0u : RT_VERTEX_HAS_COLOR));
            vertex.normal =
                mesh.normals.empty() ? float4{0, 0, 0, vertex_flags} : to_float4(mesh.normals[v], vertex_flags);
            vertex.color = mesh.colors.empty() ? float4{1, 1, 1, 1} : to_float4(mesh.colors[v]);
            glm::vec2 uv0 = mesh.uv0.empty() ? glm::vec2(0.0f) : mesh.uv0[v];
            glm::vec2 uv1 = mesh.uv1.empty() ? uv0 : mesh.uv1[v];
            vertex.uv = float4{uv0.x, uv0.y, uv1.x, uv1.y};
            vertex.tangent = mesh.tangents.empty() ? float4{0, 0, 0, 0} : to_float4(mesh.tangents[v]);
            device.vertices.push_back(vertex);
        }
        std::vector<Aabb> bounds(mesh.triangles.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            glm::uvec3 tri = mesh.triangles[t];
            uint32_t material = mesh.triangle_materials.empty() ? 0u : mesh.triangle_materials[t];
            device.triangle_shading.push_back(TriangleShading{placement.first_vertex + tri.x,
                                                              placement.first_vertex + tri.y,
                                                              placement.first_vertex + tri.z, material});
            glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
            if (degenerate(a, b, c)) {
                ++device.degenerate_triangles;
                continue;  // empty bounds: the builder leaves it out
            }
            bounds[t] = triangle_bounds(mesh.positions, tri);
            device.mesh_bounds[m].grow(bounds[t]);
        }
        if (flatten) {
            placement.bvh.primitive_order.reserve(bounds.size());
            for (uint32_t t = 0; t < bounds.size(); ++t)
                if (!bounds[t].empty()) placement.bvh.primitive_order.push_back(t);
        } else {
            const double share = double(mesh.triangles.size());
            BvhProgress mesh_progress;
            if (progress)
                mesh_progress = [&progress, triangles_placed, share, triangles_to_place](double fraction) {
                    progress((triangles_placed + fraction * share) / triangles_to_place);
                };
            placement.bvh = build_bvh(bounds, options, mesh_progress);
            triangles_placed += share;
        }
        for (uint32_t t : placement.bvh.primitive_order)
            device.triangles.push_back(triangle_geometry(mesh.positions, mesh.triangles[t], t));
        triangle_weighted_sah += double(placement.bvh.sah_cost) * placement.bvh.primitive_order.size();
        bvh_triangles += placement.bvh.primitive_order.size();
        placements.push_back(std::move(placement));
    }

    // Instances whose mesh has nothing to hit are left out of the top level (they can never be hit).
    std::vector<glm::mat4> transforms;
    std::vector<uint32_t> kept;
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const prism::Instance& instance = scene.instances[i];
        if (device.mesh_bounds[instance.mesh].empty()) continue;
        kept.push_back(static_cast<uint32_t>(i));
        transforms.push_back(instance.transform);
        device.instance_meshes.push_back(instance.mesh);
        device.traced_triangles += placements[instance.mesh].bvh.primitive_order.size();
    }
    if (kept.empty())
        throw Error(scene.source + ": scene has no triangles that can be hit (all " +
                    std::to_string(device.degenerate_triangles) + " are degenerate or none exist)");
    if (kept.size() != scene.instances.size())
        throw Error(scene.source +
                    ": an instance's mesh has only degenerate triangles");  // keeps instance ids = scene ids
    build_top_level(device, transforms, true);
    // A mesh an animation poses anew keeps its tree as built, for refits (flattened instances never move).
    const std::vector<bool> deformed = deformed_meshes(scene);
    auto keep_deformable = [&](size_t m, const Bvh& bvh, uint32_t first_vertex, uint32_t first_triangle,
                               uint32_t first_node, uint32_t first_block) {
        if (!deformed[m]) return;
        DeviceScene::DeformableMesh kept{uint32_t(m), bvh, first_vertex, uint32_t(scene.meshes[m].positions.size())};
        kept.first_triangle = first_triangle;
        kept.first_node = first_node;
        kept.first_block = first_block;
        device.deformable_meshes.push_back(std::move(kept));
    };
    // The layout's node array holds the top level first, then each mesh's BVH; the other array gets one unused
    // node (GPU APIs dislike empty buffers).
    if (flatten) {
        std::vector<uint32_t> first_triangle, triangle_count;
        for (MeshPlacement& placement : placements) {
            first_triangle.push_back(placement.first_triangle);
            triangle_count.push_back(uint32_t(placement.bvh.primitive_order.size()));
            placement.first_vertex = 0;  // reused below as the mesh's root: no mesh has its own
        }
        build_flat_instances(device, scene, first_triangle, triangle_count, progress);
        BvhNode unused{};
        set_node_box(unused, Aabb{});
        device.nodes.assign(1, unused);
    } else if (options.layout == BvhLayout::Wide) {
        device.top_level_nodes = wide_top_level_capacity(scene.instances.size());
        device.wide_nodes = top_level_wide_device_nodes(device.top_level, device.top_level_nodes);
        for (size_t m = 0; m < placements.size(); ++m) {
            MeshPlacement& placement = placements[m];
            uint32_t node_offset = static_cast<uint32_t>(device.wide_nodes.size());
            keep_deformable(m, placement.bvh, placement.first_vertex, placement.first_triangle, node_offset,
                            uint32_t(device.triangle_blocks.size()));
            rebase_wide_nodes(placement.bvh.wide_nodes, node_offset, placement.first_triangle);
            block_wide_leaves(placement.bvh.wide_nodes, device.triangles, device.triangle_blocks);
            if (!device.deformable_meshes.empty() && device.deformable_meshes.back().mesh == m)
                device.deformable_meshes.back().block_count =
                    uint32_t(device.triangle_blocks.size()) - device.deformable_meshes.back().first_block;
            device.wide_nodes.insert(device.wide_nodes.end(), placement.bvh.wide_nodes.begin(),
                                     placement.bvh.wide_nodes.end());
            placement.first_vertex = node_offset;  // reused below as the mesh's root node index
        }
        // The traversal's fixed stack must hold the deepest path: the top level's, the leave marker, a mesh's.
        uint32_t mesh_bound = 0;
        for (const prism::Instance& instance : scene.instances)
            mesh_bound =
                std::max(mesh_bound, wide_stack_bound(device.wide_nodes, placements[instance.mesh].first_vertex));
        uint32_t bound = wide_stack_bound(device.wide_nodes, 0) + 1 + mesh_bound;
        if (bound > RT_BVH_WIDE_STACK_SIZE)
            throw Error(scene.source + ": the wide BVH needs " + std::to_string(bound) +
                        " traversal stack entries, more than " + std::to_string(RT_BVH_WIDE_STACK_SIZE) +
                        " (use the stack layout)");
        BvhNode unused{};
        set_node_box(unused, Aabb{});
        device.nodes.assign(1, unused);
    } else {
        device.top_level_nodes = device.top_level.nodes.size();
        device.nodes = top_level_device_nodes(device.top_level);
        for (size_t m = 0; m < placements.size(); ++m) {
            MeshPlacement& placement = placements[m];
            uint32_t node_offset = static_cast<uint32_t>(device.nodes.size());
            keep_deformable(m, placement.bvh, placement.first_vertex, placement.first_triangle, node_offset, 0);
            rebase_nodes(placement.bvh.nodes, options.layout, node_offset, placement.first_triangle);
            device.nodes.insert(device.nodes.end(), placement.bvh.nodes.begin(), placement.bvh.nodes.end());
            placement.first_vertex = node_offset;  // reused below as the mesh's root node index
        }
        device.wide_nodes.assign(1, empty_wide_node());
        device.triangle_blocks.assign(1, TriangleBlock{});
    }
    // An instance with a material override reads its own copy of the mesh's per-triangle shading entries (vertex
    // indices and material), one copy per (mesh, material); geometry, vertices and BVH stay shared.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> override_shading;
    auto [solid, closed_solid_ms] = closed_solids.get();
    device.closed_solid_ms = closed_solid_ms;
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const prism::Instance& instance = scene.instances[i];
        const MeshPlacement& placement = placements[instance.mesh];
        uint32_t first_shading = placement.first_shading;
        if (instance.material_override != kNoMaterialOverride) {
            auto [entry, added] = override_shading.try_emplace({instance.mesh, instance.material_override},
                                                               static_cast<uint32_t>(device.triangle_shading.size()));
            if (added) {
                size_t count = scene.meshes[instance.mesh].triangles.size();
                for (size_t t = 0; t < count; ++t) {
                    TriangleShading shading = device.triangle_shading[placement.first_shading + t];
                    shading.material = instance.material_override;
                    device.triangle_shading.push_back(shading);
                }
            }
            first_shading = entry->second;
        }
        device.closed_solid_instances += solid[i] ? 1u : 0u;
        device.instances.push_back(device_instance(instance.transform, placement.first_vertex, placement.first_triangle,
                                                   first_shading,
                                                   solid[i] ? &device.mesh_bounds[instance.mesh] : nullptr));
    }

    // Materials and their texture stacks.
    for (const prism::Material& material : scene.materials) {
        device.materials.push_back(device_material(material, static_cast<uint32_t>(device.texture_layers.size())));
        for (const prism::TextureLayer& layer : material_layers(material)) {
            ::TextureLayer out{};
            out.texture_index = layer.texture;
            out.mode = static_cast<uint32_t>(layer.mode);
            out.uv_set = layer.uv_set;
            out.sampling = static_cast<uint32_t>(layer.wrap_u) | static_cast<uint32_t>(layer.wrap_v) << 2 |
                           (layer.nearest ? RT_SAMPLER_NEAREST : 0u);
            out.environment_color = to_float4(layer.environment_color);
            out.uv_row0 = to_float4(layer.uv_row0, 0.0f);
            out.uv_row1 = to_float4(layer.uv_row1, 0.0f);
            device.texture_layers.push_back(out);
        }
    }
    if (device.materials.empty()) device.materials.push_back(device_material(prism::Material{}, 0));

    std::vector<uint32_t> texel_offsets;
    for (const Texture& texture : scene.textures) {
        texel_offsets.push_back(static_cast<uint32_t>(device.texels.size()));
        device.texture_infos.push_back(TextureInfo{texel_offsets.back(), uint32_t(texture.width),
                                                   uint32_t(texture.height), uint32_t(texture.encoding)});
        device.texels.insert(device.texels.end(), texture.texels.begin(), texture.texels.end());
    }
    // The environment's textures get their own consecutive entries (a cube map is addressed as first + face).
    device.environment_kind = scene.environment.kind;
    device.environment_tint = scene.environment.color * scene.environment.intensity;
    device.environment_texture = static_cast<uint32_t>(device.texture_infos.size());
    for (uint32_t texture : scene.environment.textures)
        device.texture_infos.push_back(device.texture_infos.at(texture));
    if (device.texture_infos.empty()) {  // GPU APIs dislike empty buffers
        device.texture_infos.push_back(TextureInfo{0, 1, 1, RT_TEXENC_LINEAR8});
    }
    if (device.texels.empty()) device.texels.push_back(0xffffffffu);
    if (device.texture_layers.empty()) device.texture_layers.push_back(::TextureLayer{});

    for (const prism::Light& light : scene.lights) device.lights.push_back(device_light(light));
    device.light_count = static_cast<uint32_t>(device.lights.size());
    if (device.lights.empty()) device.lights.push_back(::Light{});  // placeholder; the frame says 0 lights
    device.ambient_light = scene.ambient_light;

    if (!flatten) device.sah_cost = bvh_triangles ? float(triangle_weighted_sah / double(bvh_triangles)) : 0.0f;
    device.bvh_build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return device;
}

void update_mesh_vertices(DeviceScene& device, uint32_t mesh, const Mesh& loaded, const DeformedVertices& posed) {
    auto found = std::find_if(device.deformable_meshes.begin(), device.deformable_meshes.end(),
                              [mesh](const DeviceScene::DeformableMesh& d) { return d.mesh == mesh; });
    if (found == device.deformable_meshes.end())
        throw Error("update_mesh_vertices: mesh " + std::to_string(mesh) + " was not built to be posed anew");
    if (posed.positions.size() != found->vertex_count || loaded.positions.size() != found->vertex_count ||
        (!posed.normals.empty() && posed.normals.size() != loaded.positions.size()) ||
        (!posed.tangents.empty() && posed.tangents.size() != loaded.positions.size()))
        throw Error("update_mesh_vertices: a pose of another size than mesh " + std::to_string(mesh));
    DeviceScene::DeformableMesh& deformable = *found;
    for (size_t v = 0; v < posed.normals.size(); ++v) {
        float4& normal = device.vertices[deformable.first_vertex + v].normal;
        normal = to_float4(posed.normals[v], normal.w);  // w: the vertex's flags
    }
    for (size_t v = 0; v < posed.tangents.size(); ++v)
        device.vertices[deformable.first_vertex + v].tangent = to_float4(posed.tangents[v]);

    Bvh& bvh = deformable.bvh;
    std::vector<Aabb> bounds(loaded.triangles.size());
    for (uint32_t t : bvh.primitive_order) bounds[t] = triangle_bounds(posed.positions, loaded.triangles[t]);
    refit_bvh(bvh, bounds);
    for (size_t i = 0; i < bvh.primitive_order.size(); ++i) {
        const uint32_t t = bvh.primitive_order[i];
        device.triangles[deformable.first_triangle + i] = triangle_geometry(posed.positions, loaded.triangles[t], t);
    }
    device.mesh_bounds[mesh] = Aabb{};
    if (!bvh.nodes.empty()) device.mesh_bounds[mesh] = node_bounds(bvh.nodes[0]);
    // The refitted tree goes where the build put it, with the same indices moved the same way.
    if (device.bvh_options.layout == BvhLayout::Wide) {
        BvhWideNodes nodes = bvh.wide_nodes;
        rebase_wide_nodes(nodes, deformable.first_node, deformable.first_triangle);
        UninitializedVector<TriangleBlock> blocks;
        block_wide_leaves(nodes, device.triangles, blocks);
        std::copy(nodes.begin(), nodes.end(), device.wide_nodes.begin() + deformable.first_node);
        // block_wide_leaves numbered the blocks from 0: they land at first_block.
        for (BvhWideNode& node : std::span(device.wide_nodes.data() + deformable.first_node, nodes.size()))
            for (uint32_t k = 0; k < RT_BVH_WIDTH; ++k)
                if (wide_lane_leaf(node, k))
                    set_wide_lane_leaf(node, k, wide_lane_first(node, k) + deformable.first_block,
                                       wide_lane_count(node, k));
        if (blocks.size() != deformable.block_count)
            throw Error("internal: a refitted wide mesh BVH has another number of triangle blocks");
        std::copy(blocks.begin(), blocks.end(), device.triangle_blocks.begin() + deformable.first_block);
    } else {
        BvhNodes nodes = bvh.nodes;
        rebase_nodes(nodes, device.bvh_options.layout, deformable.first_node, deformable.first_triangle);
        std::copy(nodes.begin(), nodes.end(), device.nodes.begin() + deformable.first_node);
    }
}

void update_lights(DeviceScene& device, const std::vector<Light>& lights) {
    if (lights.size() != device.light_count)
        throw Error("update_lights: expected " + std::to_string(device.light_count) + " lights");
    for (size_t i = 0; i < lights.size(); ++i) device.lights[i] = device_light(lights[i]);
}

void update_instance_transforms(DeviceScene& device, const std::vector<glm::mat4>& transforms, bool rebuild) {
    if (transforms.size() != device.instances.size())
        throw Error("update_instance_transforms: expected " + std::to_string(device.instances.size()) + " transforms");
    if (device.bvh_options.flatten_instances)
        throw Error(
            "update_instance_transforms: the instances of this scene are flattened into one BVH and cannot "
            "move (build it with BvhBuildOptions::flatten_instances off)");
    for (size_t i = 0; i < transforms.size(); ++i) {
        const ::Instance& old = device.instances[i];
        // A closed solid keeps its object-space bounds: the mesh does not move within its instance.
        Aabb solid{glm::vec3(old.solid_lower.x, old.solid_lower.y, old.solid_lower.z),
                   glm::vec3(old.solid_upper.x, old.solid_upper.y, old.solid_upper.z)};
        bool closed = (old.flags & RT_INSTANCE_CLOSED_SOLID) != 0u;
        device.instances[i] =
            device_instance(transforms[i], old.root, old.first_triangle, old.first_shading, closed ? &solid : nullptr);
    }
    build_top_level(device, transforms, rebuild);
    if (device.bvh_options.layout == BvhLayout::Wide) {
        BvhWideNodes top = top_level_wide_device_nodes(device.top_level, device.top_level_nodes);
        std::copy(top.begin(), top.end(), device.wide_nodes.begin());
        return;
    }
    if (device.top_level.nodes.size() != device.top_level_nodes)
        throw Error("internal: top-level BVH changed size on update");
    BvhNodes top = top_level_device_nodes(device.top_level);
    std::copy(top.begin(), top.end(), device.nodes.begin());
}

}  // namespace prism
