// PLY meshes: ASCII, binary little- and big-endian; any order of vertex/face properties and extra properties
// (a face may carry other properties before or after its index list); polygons fan-triangulated; ".gz" files
// read through zlib. Throws prism::Error "<file>: <cause>" naming the element on malformed or truncated data.
#pragma once

#include <filesystem>

#include "core/scene/scene.h"

namespace prism {

// Positions always; normals (nx ny nz; computed smooth, area-weighted, when the file has none), colours (red green blue
// [alpha], uchar or float) and UVs (u v | s t | texture_u texture_v) when present. Every triangle gets material slot 0.
Mesh load_ply(const std::filesystem::path& path);

}  // namespace prism
