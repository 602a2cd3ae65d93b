#include "viewer/scene_bounds.h"

namespace prism::viewer {

Aabb world_bounds(const Scene& scene) {
    Aabb bounds;
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= scene.meshes.size()) continue;
        for (const glm::vec3& p : scene.meshes[instance.mesh].positions)
            bounds.grow(glm::vec3(instance.transform * glm::vec4(p, 1.0f)));
    }
    return bounds;
}

}  // namespace prism::viewer
