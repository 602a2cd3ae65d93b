#include "viewer/camera_controls.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace prism::viewer {

CameraControls::CameraControls(const Camera& home) : home_(home), camera_(home) {}

void CameraControls::orbit(float yaw, float pitch) {
    glm::vec3 up = glm::normalize(camera_.up);
    glm::vec3 offset = camera_.position - camera_.target;
    float distance = glm::length(offset);
    if (distance <= 0.0f) return;
    glm::vec3 direction = offset / distance;
    // Limit pitch so the angle to the up axis stays within (5°, 175°).
    float angle_to_up = std::acos(std::clamp(glm::dot(direction, up), -1.0f, 1.0f));
    const float limit = glm::radians(5.0f);
    float new_angle = std::clamp(angle_to_up - pitch, limit, glm::pi<float>() - limit);
    pitch = angle_to_up - new_angle;
    glm::vec3 right = glm::cross(-direction, up);
    if (glm::length(right) > 1e-6f) {
        right = glm::normalize(right);
        // A positive pitch raises the eye (toward `up`): about `right` that is a negative rotation.
        direction = glm::vec3(glm::rotate(glm::mat4(1.0f), -pitch, right) * glm::vec4(direction, 0.0f));
    }
    direction = glm::vec3(glm::rotate(glm::mat4(1.0f), -yaw, up) * glm::vec4(direction, 0.0f));
    camera_.position = camera_.target + glm::normalize(direction) * distance;
}

namespace {

struct Basis {
    glm::vec3 right, up, forward;
    float distance;
};

// The camera's axes; distance 0 when eye and target coincide (no direction to move along).
Basis basis(const Camera& camera) {
    glm::vec3 up = glm::normalize(camera.up);
    glm::vec3 view = camera.target - camera.position;
    float distance = glm::length(view);
    if (distance <= 0.0f) return {glm::vec3(1, 0, 0), up, glm::vec3(0, 0, -1), 0.0f};
    glm::vec3 forward = view / distance;
    glm::vec3 right = glm::cross(forward, up);
    right = glm::length(right) > 1e-6f ? glm::normalize(right) : glm::vec3(1.0f, 0.0f, 0.0f);
    return {right, up, forward, distance};
}

}  // namespace

void CameraControls::fly(const glm::vec3& distance) {
    Basis axes = basis(camera_);
    if (axes.distance <= 0.0f) return;
    glm::vec3 move = axes.right * distance.x + axes.up * distance.y + axes.forward * distance.z;
    camera_.position += move;
    camera_.target += move;
}

void CameraControls::set_scene_bounds(const Aabb& bounds) {
    bounds_ = bounds;
    glm::vec3 extent = bounds.upper - bounds.lower;
    float diagonal = glm::all(glm::greaterThanEqual(extent, glm::vec3(0.0f))) ? glm::length(extent) : 0.0f;
    fly_speed_ = diagonal > 0.0f && std::isfinite(diagonal) ? 0.1f * diagonal : 1.0f;
}

void CameraControls::pan(const glm::vec2& pixels, int viewport_height) {
    Basis axes = basis(camera_);
    if (axes.distance <= 0.0f || viewport_height <= 0) return;
    // The height the viewport spans at the target's depth, in world units.
    float span = 2.0f * axes.distance * std::tan(glm::radians(camera_.vertical_fov_degrees) * 0.5f);
    float per_pixel = span / float(viewport_height);
    // Dragging right brings the scene right: the eye moves left.
    glm::vec3 move =
        (-axes.right * pixels.x + glm::normalize(glm::cross(axes.right, axes.forward)) * pixels.y) * per_pixel;
    camera_.position += move;
    camera_.target += move;
}

void CameraControls::frame_scene(float aspect) {
    glm::vec3 extent = bounds_.upper - bounds_.lower;
    if (!glm::all(glm::greaterThanEqual(extent, glm::vec3(0.0f)))) return;  // no bounds: nothing to frame
    float radius = std::max(0.5f * glm::length(extent), 1e-3f);
    float vertical = glm::radians(camera_.vertical_fov_degrees);
    float horizontal = 2.0f * std::atan(std::tan(vertical * 0.5f) * std::max(aspect, 1e-3f));
    float distance = radius / std::sin(0.5f * std::min(vertical, horizontal));
    Basis axes = basis(camera_);
    glm::vec3 centre = bounds_.center();
    camera_.target = centre;
    camera_.position = centre - axes.forward * distance;
}

void CameraControls::zoom(float notches) {
    glm::vec3 offset = camera_.position - camera_.target;
    float factor = std::pow(0.9f, notches);
    glm::vec3 next = offset * factor;
    if (glm::length(next) < 1e-4f) return;  // never reach the target: the basis would degenerate
    camera_.position = camera_.target + next;
}

}  // namespace prism::viewer
