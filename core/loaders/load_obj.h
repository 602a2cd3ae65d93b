// OBJ/MTL through tinyobjloader. A texture whose exact name is missing is found case-insensitively.
#pragma once

#include <filesystem>

#include "core/scene/scene.h"

namespace prism {

// Appends one mesh (per-triangle material indices), its materials and textures, and one identity instance.
void load_obj(const std::filesystem::path& path, Scene& scene);

}  // namespace prism
