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

void CameraControls::fly(const glm::vec3& step) {
    glm::vec3 up = glm::normalize(camera_.up);
    glm::vec3 view = camera_.target - camera_.position;
    float distance = glm::length(view);
    if (distance <= 0.0f) return;
    glm::vec3 forward = view / distance;
    glm::vec3 right = glm::cross(forward, up);
    right = glm::length(right) > 1e-6f ? glm::normalize(right) : glm::vec3(1.0f, 0.0f, 0.0f);
    glm::vec3 move = (right * step.x + up * step.y + forward * step.z) * distance;
    camera_.position += move;
    camera_.target += move;
}

void CameraControls::zoom(float notches) {
    glm::vec3 offset = camera_.position - camera_.target;
    float factor = std::pow(0.9f, notches);
    glm::vec3 next = offset * factor;
    if (glm::length(next) < 1e-4f) return;   // never reach the target: the basis would degenerate
    camera_.position = camera_.target + next;
}

}  // namespace prism::viewer
