// Where a scene's instances are at a moment of a sequence: their placements, with the spinning ones
// (Scene::spins, a scene file's "spin") turned about their axes.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace prism {

// One transform per instance of `scene` at `seconds` into the sequence; at 0 (and every whole turn) the
// placements as loaded.
std::vector<glm::mat4> instance_transforms_at(const Scene& scene, double seconds);

}  // namespace prism
