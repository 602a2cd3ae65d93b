#include "core/scene/scene.h"

namespace prism {

size_t Scene::triangle_count() const {
    size_t count = 0;
    for (const Instance& instance : instances) count += meshes.at(instance.mesh).triangles.size();
    return count;
}

}  // namespace prism
