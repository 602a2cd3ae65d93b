#include "apps/ray_file.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/util/error.h"

namespace prism::app {

static_assert(std::endian::native == std::endian::little, "ray files are little-endian; add byte swapping");
static_assert(sizeof(RayQuery) == 32);

std::vector<RayQuery> read_ray_file(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw Error(path + ": cannot open");
    std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    if (bytes.size() % sizeof(RayQuery) != 0)
        throw Error(path + ": size " + std::to_string(bytes.size()) +
                    " is not a multiple of 32 bytes (8 float32 per ray)");
    std::vector<RayQuery> rays(bytes.size() / sizeof(RayQuery));
    if (!rays.empty()) std::memcpy(rays.data(), bytes.data(), bytes.size());  // memcpy takes no null pointer
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayQuery& r = rays[i];
        bool finite = std::isfinite(r.origin[0]) && std::isfinite(r.origin[1]) && std::isfinite(r.origin[2]) &&
                      std::isfinite(r.direction[0]) && std::isfinite(r.direction[1]) && std::isfinite(r.direction[2]) &&
                      std::isfinite(r.tmin) && !std::isnan(r.tmax);
        if (!finite) throw Error(path + ": ray " + std::to_string(i) + " has a NaN or infinite component");
    }
    return rays;
}

}  // namespace prism::app
