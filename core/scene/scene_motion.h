// Where a scene's instances are at a moment of a sequence: their placements, with a glTF file's animation played
// (Scene::animation) and the spinning ones (Scene::spins, a scene file's "spin") turned about their axes.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace prism {

// One transform per instance of `scene` at `seconds` into the sequence. Without an animation, at 0 (and every whole
// turn) the placements as loaded; an animation's instances are where its keys put them at that time (looped).
std::vector<glm::mat4> instance_transforms_at(const Scene& scene, double seconds);

// Whether anything in `scene` moves over time (a spin, or an animation that moves an instance).
bool scene_moves(const Scene& scene);

}  // namespace prism
