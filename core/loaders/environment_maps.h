// Environment maps from files: a cube-map folder of six faces, or one equirectangular image.
#pragma once

#include <filesystem>

#include "core/scene/scene.h"

namespace prism {

// Loads `folder`/{right,left,up,down,front,back}.<png|jpg> (the Hipshot naming) as +X, -X, +Y, -Y, +Z, -Z and makes
// them scene.environment (kind CubeMap). Throws prism::Error "<face file>: <cause>" on a missing or bad face.
void load_cube_map(const std::filesystem::path& folder, Scene& scene);

// One equirectangular image (.hdr as RGBE, 8-bit images as sRGB) as scene.environment (kind Equirect).
void load_equirect_map(const std::filesystem::path& file, Scene& scene);

// True when `folder` holds all six faces load_cube_map() needs.
bool is_cube_map_folder(const std::filesystem::path& folder);

}  // namespace prism
