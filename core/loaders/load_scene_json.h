// Prism scene files (.json): camera, environment, lights, named seed materials and objects placed from model files.
// The schema is docs/scene-format.md. Throws prism::Error "<file>: <key path>: <cause>" for unknown keys and
// wrong types, so a typo is reported rather than silently ignored.
#pragma once

#include <filesystem>

#include "core/scene/scene.h"

namespace prism {

// Paths inside the file (objects, textures, environment maps) are relative to the file's own folder.
Scene load_scene_json(const std::filesystem::path& path);

}  // namespace prism
