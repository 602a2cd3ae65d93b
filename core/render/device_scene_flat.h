// The wide layout with flattened instances (BvhBuildOptions::flatten_instances): see core/render/device_scene_flat.cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "core/render/device_scene.h"

namespace prism {

// Replaces device.wide_nodes and device.triangle_blocks with one world-space BVH over every instance's triangles.
// device.triangles must hold each mesh's triangles at [first_triangle[m], first_triangle[m] + triangle_count[m])
// (degenerate ones left out), as build_device_scene lays them out.
void build_flat_instances(DeviceScene& device, const Scene& scene, const std::vector<uint32_t>& first_triangle,
                          const std::vector<uint32_t>& triangle_count, const BvhProgress& progress = {});

}  // namespace prism
