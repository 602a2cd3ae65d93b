// `prism rays`: closest-hit (or any-hit) queries for rays from a file, on any backend (docs/ray-queries.md);
// with --bench, their throughput on several backends (apps/rays_bench.h).
// IN: N records of 8 little-endian float32 (origin xyz, tmin, direction xyz, tmax).
// OUT: N records of 20 bytes (float32 t, uint32 instance, uint32 primitive, float32 u, float32 v).
#include <chrono>
#include <cmath>
#include <cstdio>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/option_checks.h"
#include "apps/ray_file.h"
#include "apps/rays_bench.h"
#include "apps/scene_options.h"
#include "core/util/error.h"
#include "core/util/output_file.h"
#include "core/render/render_engine.h"

namespace prism::app {
namespace {

struct RaysOptions {
    SceneOptions scene;
    std::string backend = "auto";
    std::string in;
    std::string out;
    bool any_hit = false;
    bool bench = false;
    RaysBenchOptions bench_options;
};

void run_rays(RaysOptions& options) {
    if (options.bench) {
        if (!options.out.empty() || options.any_hit)
            throw Error("rays --bench measures closest hits and writes --json, not --out or --any-hit");
        options.bench_options.scene = options.scene;
        options.bench_options.rays_file = options.in;
        run_rays_bench(options.bench_options);
        return;
    }
    if (options.in.empty() || options.out.empty()) throw Error("rays: --rays and --out are required (or --bench)");
    route_output();
    check_backend_option(options.backend);  // options before any work
    check_writable_option("--out", options.out);
    std::vector<RayQuery> rays = read_ray_file(options.in);
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
    command->add_option("--rays", options->in, "input rays: 8 float32 each (with --bench: optional)");
    add_output_option(command, options->out, "output hits: 20 bytes each");
    command->add_flag("--any-hit", options->any_hit, "report any hit (occlusion) instead of the closest");
    RaysBenchOptions& bench = options->bench_options;
    command->add_flag("--bench", options->bench,
                      "measure device-time Mrays/s on --backends instead (without --rays: primary rays of a "
                      "--width x --height camera on +z framing the scene, then one diffuse ray per hit)");
    command->add_option("--backends", bench.backends, "--bench: comma-separated backends")->capture_default_str();
    command->add_option("--width", bench.width, "--bench: primary rays across")->capture_default_str();
    command->add_option("--height", bench.height, "--bench: primary rays down")->capture_default_str();
    command
        ->add_option("--runs", bench.runs,
                     "--bench: timed launches (median reported), back to back on rays uploaded once and, "
                     "apart, each after its rays' upload")
        ->capture_default_str();
    command->add_option("--warmup", bench.warmup, "--bench: untimed launches before the timed back-to-back ones")
        ->capture_default_str();
    command
        ->add_option("--ray-order", bench.ray_order,
                     "--bench: made (as made or read), coherent (each set sorted by direction octant, then origin "
                     "along a Morton curve, before it is traced: what reordering would give) or two-point (sorted "
                     "by a Morton code of the origin and a point along the ray)")
        ->check(CLI::IsMember({"made", "coherent", "two-point"}))
        ->capture_default_str();
    add_json_option(command, bench.json, "--bench: results as JSON");
    command->callback([options] { run_rays(*options); });
}

}  // namespace prism::app
