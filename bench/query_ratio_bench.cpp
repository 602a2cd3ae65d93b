// Dev harness: cpu ray queries vs Embree rtcIntersect1 on the oracle rays. Single-threaded, timed in thread CPU
// time (a busy machine preempts both alike without counting), alternating the two every round.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "bench/embree_oracle.h"
#include "core/backend.h"
#include "core/renderer.h"
#include "core/scene_loader.h"

namespace prism { void register_builtin_backends(); }
using namespace prism;

static double cpu_ms() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
static double wall_ms() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
static double med(std::vector<double> v) { std::sort(v.begin(), v.end()); return v[v.size() / 2]; }

int main(int argc, char** argv) {
    register_builtin_backends();
    std::vector<std::string> scenes;
    int rounds = 5;
    const char* env = std::getenv("QB_LAYOUT");
    std::string layout = env ? env : "stack";
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--rounds") rounds = std::atoi(argv[++i]);
        else scenes.push_back(a);
    }
    for (const std::string& path : scenes) {
        Scene scene = load_scene(path);
        BvhBuildOptions options;
        if (layout == "escape") options.layout = BvhLayout::Escape;
#ifdef RT_BVH_LAYOUT_WIDE
        if (layout == "wide") options.layout = BvhLayout::Wide;
#endif
        if (std::getenv("QB_LEAF")) options.max_leaf_size = std::atoi(std::getenv("QB_LEAF"));
        if (std::getenv("QB_BINS")) options.bins = std::atoi(std::getenv("QB_BINS"));
        if (std::getenv("QB_TCOST")) options.traversal_cost = std::atof(std::getenv("QB_TCOST"));
        DeviceScene device = build_device_scene(scene, options);
        const char* threads_env = std::getenv("QB_THREADS");
        unsigned threads = threads_env ? unsigned(std::atoi(threads_env)) : 1u;
        auto clock = threads == 1 ? cpu_ms : wall_ms;   // one thread: thread CPU time; more: wall time
        oracle::EmbreeScene embree(scene, threads);
        oracle::OracleRays rays = oracle::make_oracle_rays(scene, embree, 500000, 1000000, 7);
        std::vector<RayQuery> sets[3] = {
            std::vector<RayQuery>(rays.rays.begin(), rays.rays.begin() + long(rays.primary)),
            std::vector<RayQuery>(rays.rays.begin() + long(rays.primary), rays.rays.end()),
            std::vector<RayQuery>(rays.rays.begin(), rays.rays.begin() + long(rays.primary))};
        for (RayQuery& q : sets[2]) for (int k = 0; k < 3; ++k) q.direction[k] = -q.direction[k];
        std::unique_ptr<Backend> backend = create_backend("cpu:" + std::to_string(threads));
        Renderer renderer(*backend, device);
        for (int s = 0; s < (std::getenv("QB_MISS") ? 3 : 2); ++s) {
            std::vector<double> mine, theirs;
            std::vector<RayHit> mine_hits = renderer.trace(sets[s], false);   // uploads the rays
            std::vector<RayHit> embree_hits = embree.intersect1(sets[s]);
            oracle::Agreement agreement = oracle::compare_hits(mine_hits, embree_hits);
            for (int r = 0; r < rounds; ++r) {
                double t0 = clock();
                backend->enqueue(Stage::Intersect, 0);
                backend->finish();
                double t1 = clock();
                embree.intersect1(sets[s]);
                double t2 = clock();
                mine.push_back(t1 - t0);
                theirs.push_back(t2 - t1);
            }
            double n = double(sets[s].size());
            double mb = *std::min_element(mine.begin(), mine.end()), eb = *std::min_element(theirs.begin(), theirs.end());
            std::printf("%-14s %-7s cpu %6.2f Mr/s (med %6.2f)  embree %6.2f (med %6.2f)  ratio best %.3f med %.3f  agree %.5f\n",
                        path.substr(path.find_last_of('/') + 1).c_str(), s == 2 ? "miss" : s ? "diffuse" : "primary", n / mb / 1e3,
                        n / med(mine) / 1e3, n / eb / 1e3, n / med(theirs) / 1e3, eb / mb, med(theirs) / med(mine),
                        agreement.fraction());
        }
    }
}
