// Where a scene's instances, lights and camera are at a moment of a sequence: their placements, with a glTF file's
// animation played (Scene::animation) and the spinning instances (Scene::spins, a scene file's "spin") turned about
// their axes.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace prism {

// One transform per instance of `scene` at `seconds` into the sequence. Without an animation, at 0 (and every whole
// turn) the placements as loaded; an animation's instances are where its keys put them at that time (looped).
std::vector<glm::mat4> instance_transforms_at(const Scene& scene, double seconds);

// The scene's lights at `seconds` into the sequence: those hanging from an animated node where it puts them (a light
// whose node gives no finite place keeps the one it has), the rest as loaded.
std::vector<Light> lights_at(const Scene& scene, double seconds);

// Whether anything in `scene` moves over time (a spin, or an animation that moves an instance or the camera).
bool scene_moves(const Scene& scene);

// The scene's camera at `seconds` into the sequence: where the animation puts the node it hangs from, else as loaded.
Camera camera_at(const Scene& scene, double seconds);

// A camera placed by a node's world transform as glTF places one: at the node's origin, looking down its -z with
// its +y up (the field of view is kept). False, and `camera` untouched, when the transform gives no finite frame.
bool place_camera_at_node(Camera& camera, const glm::mat4& world);

}  // namespace prism
