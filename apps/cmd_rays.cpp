// `prism rays`: closest-hit (or any-hit) queries for rays from a file, on any backend (docs/ray-queries.md).
// IN: N records of 8 little-endian float32 (origin xyz, tmin, direction xyz, tmax).
// OUT: N records of 20 bytes (float32 t, uint32 instance, uint32 primitive, float32 u, float32 v).
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <chrono>
#include <cmath>
#include <iterator>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/option_checks.h"
#include "apps/scene_options.h"
#include "core/util/error.h"
#include "core/util/output_file.h"
#include "core/render/render_engine.h"

namespace prism::app {
namespace {

static_assert(std::endian::native == std::endian::little, "ray files are little-endian; add byte swapping");

struct RaysOptions {
    SceneOptions scene;
    std::string backend = "auto";
    std::string in;
    std::string out;
    bool any_hit = false;
};

std::vector<RayQuery> read_rays(const std::string& path) {
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

void run_rays(const RaysOptions& options) {
    route_output();
    check_backend_option(options.backend);  // options before any work
    check_writable_option("--out", options.out);
    std::vector<RayQuery> rays = read_rays(options.in);
    LoadedScene loaded = load_and_build(options.scene, options.backend);
    RenderEngine engine(options.backend, loaded.device);
    auto start = std::chrono::steady_clock::now();
    std::vector<RayHit> hits = engine.trace(rays, options.any_hit);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    static_assert(sizeof(RayHit) == 20);
    write_file_atomically(options.out,
                          std::string_view(reinterpret_cast<const char*>(hits.data()), hits.size() * sizeof(RayHit)));
    size_t hit_count = 0;
    for (const RayHit& h : hits) hit_count += h.t < INFINITY;
    std::printf("prism rays: %zu rays on %s: %zu hits, %.1f ms (%.2f Mrays/s incl. upload) -> %s\n", rays.size(),
                engine.info().name.c_str(), hit_count, ms, double(rays.size()) / (ms * 1e3), options.out.c_str());
}

}  // namespace

void add_rays_command(CLI::App& app) {
    auto options = std::make_shared<RaysOptions>();
    auto* command = app.add_subcommand("rays", "Trace rays from a file and write their hits (docs/ray-queries.md)");
    add_scene_options(command, options->scene, true);
    command->add_option("--backend", options->backend, "backend (as for render)")->capture_default_str();
    command->add_option("--rays", options->in, "input rays: 8 float32 each")->required();
    add_output_option(command, options->out, "output hits: 20 bytes each")->required();
    command->add_flag("--any-hit", options->any_hit, "report any hit (occlusion) instead of the closest");
    command->callback([options] { run_rays(*options); });
}

}  // namespace prism::app
