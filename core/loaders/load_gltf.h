// glTF 2.0 (.gltf with external or embedded buffers/images, .glb) through tinygltf.
#pragma once

#include <filesystem>
#include <string>

#include "core/scene/scene.h"

namespace prism {

// Appends meshes, instances (node hierarchy flattened to world transforms), materials, textures, cameras (the
// first becomes scene.camera) and KHR_lights_punctual lights, and sets scene.animation to the animation that
// `animation` names (gltf_animation.h: empty for the first, a number, a name, or "all").
void load_gltf(const std::filesystem::path& path, Scene& scene, const std::string& animation = {});

}  // namespace prism
