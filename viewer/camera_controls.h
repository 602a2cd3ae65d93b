// Orbit, fly, pan, zoom and framing on a prism::Camera. Pure math (no GL, no GLFW) so it is unit-tested on its own.
#pragma once

#include <glm/glm.hpp>

#include "core/bvh/bvh.h"
#include "core/scene/scene.h"

namespace prism::viewer {

class CameraControls {
public:
    explicit CameraControls(const Camera& home);

    const Camera& camera() const { return camera_; }
    void reset() { camera_ = home_; }

    // Turns the eye around the target: yaw about the up axis (positive: the eye moves left, the scene seems to
    // turn right, as when dragging right), pitch about the camera's right axis (positive: the eye rises, as when
    // dragging down). Radians. Pitch stops 5 degrees short of the poles so the view never flips.
    void orbit(float yaw, float pitch);
    // Moves eye and target together by `camera_axes_distance` world units, in camera axes: x right, y up (world
    // up), z forward.
    void fly(const glm::vec3& camera_axes_distance);
    // Held fly keys: `seconds` held per camera axis (viewer/held_keys.h) at fly_speed() units per second.
    void fly_for(const glm::vec3& seconds) { fly(seconds * fly_speed_); }
    // The scene's bounds set the fly speed (a tenth of their diagonal per second: any scene, large or small, is
    // crossed in about ten seconds) and what frame_scene() shows.
    void set_scene_bounds(const Aabb& bounds);
    float fly_speed() const { return fly_speed_; }
    // Middle-button or Shift drag: moves eye and target together in the view plane so that what lies at the
    // target's depth follows the pointer. Pixels (x right, y down) in a viewport `viewport_height` pixels high.
    void pan(const glm::vec2& pixels, int viewport_height);
    // F: looks at the centre of the scene's bounds from the current direction, from just far enough that their
    // bounding sphere fits the narrower field of view (`aspect`: width / height).
    void frame_scene(float aspect);
    // Scroll: each notch moves the eye 10% of the way toward (positive) or away from the target.
    void zoom(float notches);

private:
    Camera home_;
    Camera camera_;
    Aabb bounds_;
    float fly_speed_ = 1.0f;
};

}  // namespace prism::viewer
