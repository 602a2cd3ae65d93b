#include "core/scene/scene_motion.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace prism {

std::vector<glm::mat4> instance_transforms_at(const Scene& scene, double seconds) {
    std::vector<glm::mat4> transforms;
    transforms.reserve(scene.instances.size());
    for (const Instance& instance : scene.instances) transforms.push_back(instance.transform);
    apply_node_animation(scene.animation, seconds, transforms);
    for (const InstanceSpin& spin : scene.spins) {
        // The turn is reduced to [0, 1) in double first, so a whole turn gives the loaded placement exactly.
        double turns = std::fmod(seconds / double(spin.seconds), 1.0);
        if (turns == 0.0) continue;
        float angle = static_cast<float>(turns * 2.0 * 3.14159265358979323846);
        glm::mat4 about_pivot = glm::translate(glm::mat4(1.0f), spin.pivot) *
                                glm::rotate(glm::mat4(1.0f), angle, spin.axis) *
                                glm::translate(glm::mat4(1.0f), -spin.pivot);
        transforms[spin.instance] = about_pivot * transforms[spin.instance];
    }
    return transforms;
}

std::vector<Light> lights_at(const Scene& scene, double seconds) {
    std::vector<Light> lights = scene.lights;
    const NodeAnimation& animation = scene.animation;
    if (!animation.plays() || animation.lights.empty()) return lights;
    const std::vector<glm::mat4> world = node_world_transforms(animation, seconds);
    for (const AnimatedLight& animated : animation.lights) {
        const glm::mat4& node = world[animated.node];
        const glm::vec3 position = node * glm::vec4(0, 0, 0, 1);
        const glm::vec3 axis = glm::vec3(node * glm::vec4(0, 0, -1, 0));
        const glm::vec3 direction = glm::normalize(axis);
        bool finite = glm::dot(axis, axis) > 0.0f;
        for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(position[i]) && std::isfinite(direction[i]);
        if (!finite) continue;
        Light& light = lights.at(animated.light);
        light.position = position;
        light.direction = direction;
    }
    return lights;
}

bool scene_moves(const Scene& scene) { return !scene.spins.empty() || scene.animation.plays(); }

Camera camera_at(const Scene& scene, double seconds) {
    Camera camera = scene.camera;
    const NodeAnimation& animation = scene.animation;
    if (animation.plays() && animation.camera_node >= 0)
        place_camera_at_node(camera, node_world_transforms(animation, seconds)[size_t(animation.camera_node)]);
    return camera;
}

bool place_camera_at_node(Camera& camera, const glm::mat4& world) {
    const glm::vec3 position = world * glm::vec4(0, 0, 0, 1);
    const glm::vec3 forward = glm::normalize(glm::vec3(world * glm::vec4(0, 0, -1, 0)));
    const glm::vec3 up = glm::normalize(glm::vec3(world * glm::vec4(0, 1, 0, 0)));
    const glm::vec3 target = position + forward;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(position[i]) || !std::isfinite(target[i]) || !std::isfinite(up[i])) return false;
    camera.position = position;
    camera.target = target;
    camera.up = up;
    return true;
}

}  // namespace prism
