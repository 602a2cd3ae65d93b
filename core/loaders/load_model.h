// One model file of any supported format appended to a scene: the piece shared by bare-model loading and the
// objects of a Prism scene file.
#pragma once

#include <filesystem>
#include <string>

#include "core/scene/scene.h"

namespace prism {

enum class ModelFormat { Gltf, Obj, Ply, SceneJson, Unknown };

// By extension, ignoring case: .gltf/.glb, .obj, .ply/.ply.gz, .json.
ModelFormat model_format(const std::filesystem::path& path);

// Appends the meshes, instances, materials and textures (and glTF cameras/lights) of a .gltf/.glb/.obj/.ply(.gz).
// Triangles without a material of their own (every PLY) get default_material(). Throws prism::Error
// "<file>: unsupported scene format" for anything else. `animation` picks a glTF file's animation (load_gltf.h);
// given for another format it is an error naming the file.
void load_model(const std::filesystem::path& path, Scene& scene, const std::string& animation = {});

}  // namespace prism
