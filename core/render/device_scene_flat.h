// Flattened instances (BvhBuildOptions::flatten_instances), wide or stack layout: see
// core/render/device_scene_flat.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "core/render/device_scene.h"

namespace prism {

// Builds one world-space BVH over every instance's triangles in device.bvh_options.layout (wide: wide_nodes and
// triangle_blocks; stack: nodes, with world-space triangles appended to device.triangles); the other layout's arrays
// get one unused entry. device.triangles must hold each mesh's triangles at [first_triangle[m], first_triangle[m] +
// triangle_count[m]) in file order (degenerate ones left out), as build_device_scene lays them out.
void build_flat_instances(DeviceScene& device, const Scene& scene, const std::vector<uint32_t>& first_triangle,
                          const std::vector<uint32_t>& triangle_count, const BvhProgress& progress = {});

}  // namespace prism
