// frame_scene (declared in core/loaders/scene_loader.h): a camera that sees the whole scene.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/loaders/scene_loader.h"

namespace prism {

void frame_scene(Scene& scene) {
    glm::vec3 low(std::numeric_limits<float>::max()), high(std::numeric_limits<float>::lowest());
    std::vector<glm::vec3> mesh_low(scene.meshes.size(), low), mesh_high(scene.meshes.size(), high);
    for (size_t m = 0; m < scene.meshes.size(); ++m)
        for (const glm::vec3& p : scene.meshes[m].positions) {
            mesh_low[m] = glm::min(mesh_low[m], p);
            mesh_high[m] = glm::max(mesh_high[m], p);
        }
    // World bounds from each instance's object-space box corners: a little loose under rotation, never too tight.
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= scene.meshes.size() || scene.meshes[instance.mesh].positions.empty()) continue;
        for (int corner = 0; corner < 8; ++corner) {
            glm::vec3 object{(corner & 1) ? mesh_high[instance.mesh].x : mesh_low[instance.mesh].x,
                             (corner & 2) ? mesh_high[instance.mesh].y : mesh_low[instance.mesh].y,
                             (corner & 4) ? mesh_high[instance.mesh].z : mesh_low[instance.mesh].z};
            glm::vec3 world = glm::vec3(instance.transform * glm::vec4(object, 1.0f));
            low = glm::min(low, world);
            high = glm::max(high, world);
        }
    }
    if (low.x > high.x) return;  // nothing to look at: keep the default camera

    glm::vec3 centre = (low + high) * 0.5f;
    float radius = std::max(glm::length(high - low) * 0.5f, 1e-6f);
    float half_fov = glm::radians(scene.camera.vertical_fov_degrees) * 0.5f;
    // The bounding sphere just fits the vertical field of view (the horizontal one is wider for landscape images).
    float distance = radius / std::sin(half_fov);
    glm::vec3 diagonal = glm::normalize(glm::vec3(1.0f, 0.6f, 1.0f));
    scene.camera.position = centre + diagonal * distance;
    scene.camera.target = centre;
    scene.camera.up = {0.0f, 1.0f, 0.0f};
}

}  // namespace prism
