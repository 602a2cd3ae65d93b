// query_ratio_bench: the cpu backend's ray queries against Embree rtcIntersect1 on the oracle rays (1M per model,
// half primary, half diffuse), made to be read on a busy shared machine while tuning the traversal:
//  - one thread by default, timed in thread CPU time: a preempted run does not count the time it waited;
//  - the cpu backend's intersect launch re-run on rays already uploaded (no host conversion in the time) and
//    Embree's intersect1 alternate round by round, so cache and memory contention from other work hits both;
//  - prints the best and the median round of each and their ratios, and the hit agreement with Embree.
// `prism bench --embree` (2 threads, wall time) is the reference measurement; this is the tuning loop.
// The wide layout flattens the scene's instances, as `prism bench` builds it; --two-level keeps the top level.
//   query_ratio_bench [--rounds N] [--threads N] [--bvh-layout wide|stack|escape] [--bvh-leaf N] [--two-level] scene...
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "backends/backend_list.h"
#include "bench/embree_oracle.h"
#include "core/render/backend.h"
#include "core/render/render_engine.h"
#include "core/render/renderer.h"
#include "core/loaders/scene_loader.h"
#include "core/util/median.h"

namespace {

using namespace prism;

double thread_cpu_ms() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double wall_ms() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("cpu ray queries against Embree rtcIntersect1, interleaved (see the source's header)");
    std::vector<std::string> scenes;
    int rounds = 5;
    unsigned threads = 1;
    std::string layout = "wide";
    uint32_t leaf = 0, wide_leaf = 0;
    bool two_level = false;
    app.add_option("scenes", scenes, "models (.ply, .ply.gz, ...)")->required();
    app.add_option("--rounds", rounds, "timed rounds after one warm-up")->capture_default_str();
    app.add_option("--threads", threads, "threads for both (1: thread CPU time; more: wall time)")
        ->capture_default_str();
    app.add_option("--bvh-layout", layout, "stack, escape or wide")->capture_default_str();
    app.add_option("--bvh-leaf", leaf, "max_leaf_size of the BVH build (0: the default)");
    app.add_option("--wide-leaf", wide_leaf, "wide_leaf_size of the BVH build (0: the default)");
    app.add_flag("--two-level", two_level, "wide layout: keep the top level over instances (as `prism view`)");
    CLI11_PARSE(app, argc, argv);
    try {
        register_builtin_backends();
        auto clock = threads == 1 ? thread_cpu_ms : wall_ms;
        for (const std::string& path : scenes) {
            Scene scene = load_scene(path);
            BvhBuildOptions options;
            options.layout = resolve_bvh_layout(layout, "cpu");
            if (leaf) options.max_leaf_size = leaf;
            if (wide_leaf) options.wide_leaf_size = wide_leaf;
            options.flatten_instances = !two_level;
            DeviceScene device = build_device_scene(scene, options);
            oracle::EmbreeScene embree(scene, threads);
            oracle::OracleRays rays = oracle::make_oracle_rays(scene, embree, 500000, 1000000, 7);
            std::vector<RayQuery> sets[2] = {
                std::vector<RayQuery>(rays.rays.begin(), rays.rays.begin() + long(rays.primary)),
                std::vector<RayQuery>(rays.rays.begin() + long(rays.primary), rays.rays.end())};
            std::unique_ptr<Backend> backend = create_backend("cpu:" + std::to_string(threads));
            Renderer renderer(*backend, device);
            std::string name = path.substr(path.find_last_of('/') + 1);
            for (int s = 0; s < 2; ++s) {
                // trace() uploads the rays and is the warm-up; the timed rounds re-run its intersect launch.
                oracle::Agreement agreement =
                    oracle::compare_hits(renderer.trace(sets[s], false), embree.intersect1(sets[s]));
                std::vector<double> cpu, reference;
                for (int r = 0; r < rounds; ++r) {
                    double t0 = clock();
                    backend->enqueue(renderer.query_stage(false), 0);
                    backend->finish();
                    double t1 = clock();
                    embree.intersect1(sets[s]);
                    double t2 = clock();
                    cpu.push_back(t1 - t0);
                    reference.push_back(t2 - t1);
                }
                double n = double(sets[s].size());
                double cpu_best = *std::min_element(cpu.begin(), cpu.end());
                double reference_best = *std::min_element(reference.begin(), reference.end());
                std::printf(
                    "%-14s %-7s cpu %6.2f Mrays/s (median %6.2f)  embree %6.2f (median %6.2f)  ratio best %.3f "
                    "median %.3f  agree %.5f\n",
                    name.c_str(), s ? "diffuse" : "primary", n / cpu_best / 1e3, n / median(cpu) / 1e3,
                    n / reference_best / 1e3, n / median(reference) / 1e3, reference_best / cpu_best,
                    median(reference) / median(cpu), agreement.fraction());
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "query_ratio_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
