// Orbit, fly and zoom on a prism::Camera. Pure math (no GL, no GLFW) so it is unit-tested on its own.
#pragma once

#include <glm/glm.hpp>

#include "core/scene.h"

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
    // Moves eye and target together, in camera axes: x right, y up (world up), z forward. Units are scaled by
    // the eye-target distance, so one step is the same fraction of the view in any scene.
    void fly(const glm::vec3& camera_axes_step);
    // Scroll: each notch moves the eye 10% of the way toward (positive) or away from the target.
    void zoom(float notches);

private:
    Camera home_;
    Camera camera_;
};

}  // namespace prism::viewer
