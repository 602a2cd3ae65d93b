// BVH build time and quality over the scaling series (../shared/scenes/SOURCES.md): binned SAH vs the seed's median
// split, on one thread and on all of them. Build time is the median of --runs builds (tree + flattening, stack layout);
// quality is the SAH cost (traversal and intersection cost 1). Writes JSON with the common result header.
// Process CPU time is recorded beside wall time: on a shared machine the wall time includes waiting for a core
// (the load average at the start is recorded too), while CPU time over wall time shows how parallel a build ran.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/bench_json.h"
#include "core/bvh/bvh.h"
#include "core/util/error.h"
#include "core/loaders/load_obj.h"
#include "core/loaders/load_ply.h"
#include "core/scene/scene.h"
#include "core/util/median.h"

namespace {

using prism::Aabb;
using prism::median;
namespace fs = std::filesystem;

struct SeriesEntry {
    std::string name;
    std::string file;  // relative to the scenes folder
};

const SeriesEntry kSeries[] = {
    {"dragon_res4", "stanford/dragon_res4.ply.gz"},
    {"dragon_res3", "stanford/dragon_res3.ply.gz"},
    {"bunny", "stanford/bunny.ply"},
    {"dragon_res2", "stanford/dragon_res2.ply.gz"},
    {"conference", "mcguire/conference/conference.obj"},
    {"dragon", "stanford/dragon.ply.gz"},
};

// Triangle bounds the way the scene code hands them over: empty for triangles no ray can hit.
void append_bounds(const prism::Mesh& mesh, const glm::mat4& transform, std::vector<Aabb>& bounds) {
    for (const auto& triangle : mesh.triangles) {
        glm::vec3 a = glm::vec3(transform * glm::vec4(mesh.positions[triangle.x], 1.0f));
        glm::vec3 b = glm::vec3(transform * glm::vec4(mesh.positions[triangle.y], 1.0f));
        glm::vec3 c = glm::vec3(transform * glm::vec4(mesh.positions[triangle.z], 1.0f));
        glm::vec3 normal = glm::cross(b - a, c - a);
        float area2 = glm::dot(normal, normal);
        Aabb box;
        if (area2 > 0.0f && std::isfinite(area2)) {
            box.grow(a);
            box.grow(b);
            box.grow(c);
        }
        bounds.push_back(box);
    }
}

// All triangles of the file as one soup (world space), or an empty list when no loader for it is built in.
std::vector<Aabb> load_triangle_bounds(const fs::path& path) {
    std::vector<Aabb> bounds;
    std::string name = path.filename().string();
    if (name.ends_with(".ply") || name.ends_with(".ply.gz")) {
        append_bounds(prism::load_ply(path), glm::mat4(1.0f), bounds);
    } else if (name.ends_with(".obj")) {
        prism::Scene scene;
        prism::load_obj(path, scene);
        for (const auto& instance : scene.instances)
            append_bounds(scene.meshes[instance.mesh], instance.transform, bounds);
    }
    return bounds;
}

std::string default_host_name() {
    char name[256] = {};
    if (gethostname(name, sizeof name - 1) != 0 || name[0] == 0) return "unknown";
    return name;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"BVH build time and SAH cost over the scaling series"};
    std::string scenes_dir = std::string(PRISM_SOURCE_DIR) + "/../shared/scenes";
    std::string out = std::string(PRISM_SOURCE_DIR) + "/bench/results/bvh-build-" + default_host_name() + ".json";
    int runs = 5;
    std::vector<std::string> only;
    app.add_option("--scenes", scenes_dir, "folder of the shared test scenes");
    app.add_option("--out", out, "JSON result file");
    app.add_option("--runs", runs, "builds per configuration (the median is reported)")->check(CLI::PositiveNumber);
    app.add_option("--only", only, "scene names to run (default: the whole series)");
    CLI11_PARSE(app, argc, argv);

    try {
        uint32_t all_threads = std::max(1u, std::thread::hardware_concurrency());
        std::vector<uint32_t> thread_counts{1};
        if (all_threads > 1) thread_counts.push_back(all_threads);

        nlohmann::json result = prism::bench::result_header();
        result["benchmark"] = "bvh_build";
        result["runs"] = runs;
        result["layout"] = "stack";
        result["max_leaf_size"] = prism::BvhBuildOptions{}.max_leaf_size;
        result["bins"] = prism::BvhBuildOptions{}.bins;
        double load[3] = {0, 0, 0};
        if (getloadavg(load, 3) == 3) result["load_average_at_start"] = {load[0], load[1], load[2]};
        result["results"] = nlohmann::json::array();
        result["skipped"] = nlohmann::json::array();

        std::printf("%-12s %9s %-7s %7s %11s %11s %11s %9s %9s %6s\n", "scene", "triangles", "method", "threads",
                    "build ms", "cpu ms", "Mtri/s", "SAH cost", "nodes", "depth");
        for (const auto& entry : kSeries) {
            if (!only.empty() && std::find(only.begin(), only.end(), entry.name) == only.end()) continue;
            fs::path path = fs::path(scenes_dir) / entry.file;
            if (!fs::exists(path)) {
                std::printf("%-12s skipped: %s not found\n", entry.name.c_str(), path.string().c_str());
                result["skipped"].push_back({{"scene", entry.name}, {"reason", "file not found"}});
                continue;
            }
            std::vector<Aabb> bounds = load_triangle_bounds(path);
            if (bounds.empty()) {
                std::printf("%-12s skipped: no loader for %s in this build\n", entry.name.c_str(),
                            path.filename().string().c_str());
                result["skipped"].push_back({{"scene", entry.name}, {"reason", "no loader in this build"}});
                continue;
            }
            for (prism::BvhMethod method : {prism::BvhMethod::BinnedSah, prism::BvhMethod::Median}) {
                const char* method_name = method == prism::BvhMethod::BinnedSah ? "sah" : "median";
                for (uint32_t threads : thread_counts) {
                    prism::BvhBuildOptions options;
                    options.method = method;
                    options.threads = threads;
                    std::vector<double> times, cpu_times;
                    prism::Bvh bvh;
                    for (int run = 0; run < runs; ++run) {
                        std::clock_t cpu_start = std::clock();
                        bvh = prism::build_bvh(bounds, options);
                        cpu_times.push_back(1e3 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
                        times.push_back(bvh.build_ms);
                    }
                    double ms = median(times);
                    double cpu_ms = median(cpu_times);
                    double rate = double(bounds.size()) / (ms * 1e3);
                    std::printf("%-12s %9zu %-7s %7u %11.1f %11.1f %11.2f %9.2f %9zu %6u\n", entry.name.c_str(),
                                bounds.size(), method_name, threads, ms, cpu_ms, rate, bvh.sah_cost, bvh.nodes.size(),
                                bvh.depth);
                    std::fflush(stdout);
                    result["results"].push_back({{"scene", entry.name},
                                                 {"file", entry.file},
                                                 {"triangles", bounds.size()},
                                                 {"bvh_primitives", bvh.primitive_order.size()},
                                                 {"method", method_name},
                                                 {"threads", threads},
                                                 {"build_ms_median", ms},
                                                 {"build_ms_runs", times},
                                                 {"cpu_ms_median", cpu_ms},
                                                 {"sah_cost", bvh.sah_cost},
                                                 {"nodes", bvh.nodes.size()},
                                                 {"depth", bvh.depth}});
                }
            }
        }
        prism::bench::write_result(out, result);
    } catch (const prism::Error& error) {
        std::fprintf(stderr, "bvh_build_bench: %s\n", error.what());
        return 1;
    }
    return 0;
}
