// glTF 2.0 (.gltf with external or embedded buffers/images, .glb) through tinygltf.
#pragma once

#include <filesystem>

#include "core/scene/scene.h"

namespace prism {

// Appends meshes, instances (node hierarchy flattened to world transforms), materials, textures, cameras (the
// first becomes scene.camera) and KHR_lights_punctual lights.
void load_gltf(const std::filesystem::path& path, Scene& scene);

}  // namespace prism
