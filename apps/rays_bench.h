// `prism rays --bench`: device-time throughput of closest-hit ray queries on each backend, primary and diffuse
// rays apart, with each backend's hit agreement against a reference (Embree where the build has it, else the cpu
// backend), into JSON (docs/ray-queries.md, "Benchmark").
#pragma once

#include <cstdint>
#include <string>

#include "apps/scene_options.h"

namespace prism::app {

struct RaysBenchOptions {
    SceneOptions scene;
    std::string backends = "cpu";
    std::string rays_file;  // empty: make the rays (bench/query_rays.h): primary width x height, then diffuse
    uint32_t width = 1920;
    uint32_t height = 1080;
    uint32_t runs = 21;
    uint32_t warmup = 2;
    uint32_t seed = 7;
    // "coherent" or "two-point": each set sorted by bench::coherent_order or two_point_order before tracing
    std::string ray_order = "made";
    std::string json;
};

void run_rays_bench(const RaysBenchOptions& options);

}  // namespace prism::app
