// A file that a model names (an OBJ's MTL library and textures, a PLY's TextureFile comment), found the way real
// files spell names and checked against the scene's read rules (core/util/scene_read_rules.h).
#pragma once

#include <filesystem>
#include <string>

namespace prism {

// `name` (as written, trimmed) under `directory`, each path component matched case-insensitively when the exact
// name is missing ("KAMEN.JPG" named as "kamen.jpg"). Returns an empty path when no such file exists. Throws
// prism::Error naming `referring_file` when the file lies outside what the scene may read, or when the exact name
// is a FIFO or a device (refused as what it is, not reported missing).
std::filesystem::path find_referenced_file(const std::string& referring_file, const std::string& name,
                                           const std::filesystem::path& directory);

}  // namespace prism
