// Ray files of `prism rays` (docs/ray-queries.md): N records of 8 little-endian float32 (origin xyz, tmin,
// direction xyz, tmax).
#pragma once

#include <string>
#include <vector>

#include "core/render/renderer.h"

namespace prism::app {

// Every ray of the file; a size that is not a whole number of records, or a NaN or infinite component (but tmax,
// which may be +inf), is an error naming the file (and the ray).
std::vector<RayQuery> read_ray_file(const std::string& path);

}  // namespace prism::app
