// A Scene flattened into the arrays of kernels/data_arrays.h: what every backend uploads and the reference
// renderer reads in place. Built once per scene; moving instances only refits or rebuilds the top level.
#pragma once

#include <cstdint>
#include <vector>

#include "core/render/backend.h"
#include "core/bvh/bvh.h"
#include "core/util/uninitialized_vector.h"
#include "core/scene/scene.h"
#include "kernels/types.h"

namespace prism {

struct DeviceScene {
    // One vector per scene array of kernels/data_arrays.h, named as there (the comments there say what each holds).
    // UninitializedVector: a vector sized with resize(n) is not zeroed first, so the code that sizes one writes
    // every element (the BVH builders' threads do).
#define RT_DATA_ARRAY(slot, type, name, access, role) PRISM_IF_SCENE_ARRAY(role, UninitializedVector<::type> name;)
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY

    BvhBuildOptions bvh_options;
    EnvironmentKind environment_kind = EnvironmentKind::Constant;
    uint32_t environment_texture = 0;  // first of six (cube map) or the one (equirect), in texture_infos
    glm::vec3 environment_tint{0.0f};
    glm::vec3 ambient_light{0.0f};
    uint32_t light_count = 0;  // `lights` holds a placeholder when the scene has none

    // For `prism info` and the benchmarks.
    size_t traced_triangles = 0;      // over instances, degenerate ones excluded
    size_t degenerate_triangles = 0;  // over meshes
    size_t top_level_nodes = 0;       // entries of the top level at the start of nodes (wide_nodes in the wide layout;
                                      // 0 with flattened instances, whose wide_nodes are one world-space BVH)
    float sah_cost = 0.0f;            // triangle-weighted mean SAH cost of the mesh BVHs
    double bvh_build_ms = 0.0;        // the whole build (closed_solid_ms runs beside it, on a thread of its own)
    // Instances marked RT_INSTANCE_CLOSED_SOLID (BvhBuildOptions::closed_solids) and the time their meshes' analysis
    // took (core/scene/closed_solid.h).
    size_t closed_solid_instances = 0;
    double closed_solid_ms = 0.0;

    // Top level, kept for refits: mesh object-space bounds and the built tree.
    std::vector<Aabb> mesh_bounds;
    std::vector<uint32_t> instance_meshes;
    Bvh top_level;

    // The meshes an animation poses anew (Scene::animation.deformations), kept for refits: each one's own tree and
    // where its entries are in the arrays above.
    struct DeformableMesh {
        uint32_t mesh = 0;
        Bvh bvh;  // as built, before its node and triangle indices were moved to their place in the arrays
        uint32_t first_vertex = 0, vertex_count = 0;
        uint32_t first_triangle = 0;                // its bvh.primitive_order.size() triangles follow
        uint32_t first_node = 0;                    // its bvh.nodes (bvh.wide_nodes in the wide layout) follow
        uint32_t first_block = 0, block_count = 0;  // the wide layout's triangle blocks
    };
    std::vector<DeformableMesh> deformable_meshes;

    size_t byte_size() const;
};

// Throws prism::Error (naming scene.source) when nothing traceable remains or an index exceeds a GPU format limit.
// `progress` hears the fraction of the scene's triangles placed in BVH leaves so far (build_bvh's, over all meshes).
DeviceScene build_device_scene(const Scene& scene, const BvhBuildOptions& options = {},
                               const BvhProgress& progress = {});

// Mesh `mesh` of the scene posed anew (`loaded` as the scene holds it, for its triangles; `posed` its positions,
// normals and tangents, as many as it has): its vertices and triangles rewritten and its BVH refitted in place (the
// same tree, boxes around the moved triangles; triangles left out as degenerate when it was built stay out). The
// top level then needs update_instance_transforms. Throws prism::Error for a mesh that was not built deformable
// (DeviceScene::deformable_meshes) or a pose of another size.
void update_mesh_vertices(DeviceScene& device, uint32_t mesh, const Mesh& loaded, const DeformedVertices& posed);

// The scene's lights moved (the same lights, placed anew: scene_motion.h's lights_at): `lights` rewritten. Throws
// prism::Error for another number of lights.
void update_lights(DeviceScene& device, const std::vector<Light>& lights);

// New instance transforms (same instances, same meshes): refits the top level, or rebuilds it when `rebuild`.
// Throws prism::Error for a scene built with flattened instances (BvhBuildOptions::flatten_instances).
// Only `instances` and the first `top_level_nodes` entries of `nodes` (`wide_nodes` in the wide layout) change.
void update_instance_transforms(DeviceScene& device, const std::vector<glm::mat4>& transforms, bool rebuild);

}  // namespace prism
