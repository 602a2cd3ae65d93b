// The world-space bounds of a scene (every instance's mesh vertices, transformed): what F frames and what the fly
// speed scales with.
#pragma once

#include "core/bvh/bvh.h"
#include "core/scene/scene.h"

namespace prism::viewer {

Aabb world_bounds(const Scene& scene);  // empty (Aabb::empty()) for a scene without geometry

}  // namespace prism::viewer
