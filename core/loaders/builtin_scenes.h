// The seed thesis's test scenes (chapter 7), built in code: "builtin:sphere" needs no files, "builtin:bunny" and
// "builtin:dragon" read the Stanford models (and the Miramar cube map) from LoadOptions::data_dir.
#pragma once

#include <string>
#include <vector>

#include "core/loaders/scene_loader.h"

namespace prism {

inline constexpr const char* kBuiltinPrefix = "builtin:";

// The names after "builtin:" that load_builtin_scene() knows.
std::vector<std::string> builtin_scene_names();

// `name` without the prefix. Throws prism::Error for an unknown name or a missing data file (naming the path
// and --data-dir).
Scene load_builtin_scene(const std::string& name, const LoadOptions& options);

}  // namespace prism
