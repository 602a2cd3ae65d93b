// BVH build time and quality over the scaling series (../shared/scenes/SOURCES.md): binned SAH vs the seed's median
// split, on one thread and on all of them, and Embree's builds of the same triangles when Embree is found.
// Build time is the median of --runs builds; quality is the SAH cost (traversal and intersection cost 1) that
// prism::sah_cost() gives the binary tree. Writes JSON with the common result header.
// Configurations: "sah" and "median" build the stack layout with the default 16 bins ("sah-32bins" with 32, as
// Embree bins); "sah-wide" is what the cpu
// backend pays for a static scene (build_flat_instances: the wide layout, 32 bins, so tree + flattening + the 8-wide
// collapse + the SAH cost). Embree: "embree-commit-<quality>" is rtcCommitScene of one triangle geometry (Embree's
// BVH8 with its triangle leaves); "embree-binary-<quality>" is Embree's SAH builder (rtcBuildBVH) making a binary
// tree with leaves of at most 4 over the same bounds, written as a Prism BVH so sah_cost() measures it like ours
// (leaf cost in blocks of one primitive, as "sah" counts; "-block4" counts blocks of four, as "sah-wide" does).
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

#ifdef PRISM_HAVE_EMBREE
#include "bench/embree_build.h"
#endif

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

// All triangles of a file as one mesh in world space.
struct TriangleSoup {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    void append(const prism::Mesh& mesh, const glm::mat4& transform) {
        uint32_t first = uint32_t(positions.size());
        for (const glm::vec3& p : mesh.positions) positions.push_back(glm::vec3(transform * glm::vec4(p, 1.0f)));
        for (const glm::uvec3& t : mesh.triangles) triangles.push_back(t + glm::uvec3(first));
    }
};

// Triangle bounds the way the scene code hands them over: empty for triangles no ray can hit.
std::vector<Aabb> triangle_bounds(const TriangleSoup& soup) {
    std::vector<Aabb> bounds(soup.triangles.size());
    for (size_t t = 0; t < soup.triangles.size(); ++t) {
        glm::vec3 a = soup.positions[soup.triangles[t].x];
        glm::vec3 b = soup.positions[soup.triangles[t].y];
        glm::vec3 c = soup.positions[soup.triangles[t].z];
        glm::vec3 normal = glm::cross(b - a, c - a);
        float area2 = glm::dot(normal, normal);
        if (area2 > 0.0f && std::isfinite(area2)) {
            bounds[t].grow(a);
            bounds[t].grow(b);
            bounds[t].grow(c);
        }
    }
    return bounds;
}

// An empty soup when no loader for the file is built in.
TriangleSoup load_triangles(const fs::path& path) {
    TriangleSoup soup;
    std::string name = path.filename().string();
    if (name.ends_with(".ply") || name.ends_with(".ply.gz")) {
        soup.append(prism::load_ply(path), glm::mat4(1.0f));
    } else if (name.ends_with(".obj")) {
        prism::Scene scene;
        prism::load_obj(path, scene);
        for (const auto& instance : scene.instances) soup.append(scene.meshes[instance.mesh], instance.transform);
    }
    return soup;
}

struct Configuration {
    const char* name;
    prism::BvhMethod method;
    prism::BvhLayout layout;
    uint32_t bins;
};

const Configuration kConfigurations[] = {
    {"sah", prism::BvhMethod::BinnedSah, prism::BvhLayout::Stack, 16},
    {"sah-wide", prism::BvhMethod::BinnedSah, prism::BvhLayout::Wide, 32},
    {"sah-32bins", prism::BvhMethod::BinnedSah, prism::BvhLayout::Stack, 32},
    {"median", prism::BvhMethod::Median, prism::BvhLayout::Stack, 16},
};

std::vector<std::string> configuration_names() {
    std::vector<std::string> names;
    for (const Configuration& configuration : kConfigurations) names.push_back(configuration.name);
    return names;
}

std::string default_host_name() {
    char name[256] = {};
    if (gethostname(name, sizeof name - 1) != 0 || name[0] == 0) return "unknown";
    return name;
}

// One result row: printed and appended to the JSON.
void report(nlohmann::json& results, const std::string& scene, const std::string& file, size_t triangles,
            const std::string& method, uint32_t threads, const std::vector<double>& times,
            const std::vector<double>& cpu_times, const prism::Bvh* bvh) {
    double ms = median(times);
    double cpu_ms = cpu_times.empty() ? 0.0 : median(cpu_times);
    double rate = double(triangles) / (ms * 1e3);
    nlohmann::json row = {{"scene", scene},     {"file", file},          {"triangles", triangles}, {"method", method},
                          {"threads", threads}, {"build_ms_median", ms}, {"build_ms_runs", times}};
    if (!cpu_times.empty()) row["cpu_ms_median"] = cpu_ms;
    if (bvh) {
        row["bvh_primitives"] = bvh->primitive_order.size();
        row["sah_cost"] = bvh->sah_cost;
        row["nodes"] = bvh->nodes.size();
        row["depth"] = bvh->depth;
        if (!bvh->wide_nodes.empty()) row["wide_nodes"] = bvh->wide_nodes.size();
        std::printf("%-12s %9zu %-22s %7u %11.1f %11.1f %9.2f %9.2f %9zu %6u\n", scene.c_str(), triangles,
                    method.c_str(), threads, ms, cpu_ms, rate, bvh->sah_cost, bvh->nodes.size(), bvh->depth);
    } else {
        std::printf("%-12s %9zu %-22s %7u %11.1f %11.1f %9.2f\n", scene.c_str(), triangles, method.c_str(), threads, ms,
                    cpu_ms, rate);
    }
    std::fflush(stdout);
    results.push_back(row);
}

// Each step of build_bvh (tree, flatten, collapse, sah), its median over the runs.
nlohmann::json phase_medians(const std::vector<prism::BvhBuildPhases>& runs) {
    auto of = [&runs](double prism::BvhBuildPhases::*phase) {
        std::vector<double> values;
        for (const prism::BvhBuildPhases& run : runs) values.push_back(run.*phase);
        return median(values);
    };
    return {{"tree", of(&prism::BvhBuildPhases::tree_ms)},
            {"flatten", of(&prism::BvhBuildPhases::flatten_ms)},
            {"collapse", of(&prism::BvhBuildPhases::collapse_ms)},
            {"sah", of(&prism::BvhBuildPhases::sah_ms)}};
}

double cpu_ms_since(std::clock_t start) { return 1e3 * double(std::clock() - start) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"BVH build time and SAH cost over the scaling series"};
    std::string scenes_dir = std::string(PRISM_SOURCE_DIR) + "/../shared/scenes";
    std::string out = std::string(PRISM_SOURCE_DIR) + "/bench/results/bvh-build-" + default_host_name() + ".json";
    int runs = 5;
    std::vector<std::string> only;
    std::vector<std::string> methods;
    std::vector<uint32_t> thread_counts;
    bool embree = true;
    app.add_option("--scenes", scenes_dir, "folder of the shared test scenes");
    app.add_option("--out", out, "JSON result file");
    app.add_option("--runs", runs, "builds per configuration (the median is reported)")->check(CLI::PositiveNumber);
    app.add_option("--only", only, "scene names to run (default: the whole series)")->delimiter(',');
    app.add_option("--methods", methods,
                   "Prism configurations to run: sah, sah-wide, sah-32bins, median (default: all)")
        ->delimiter(',')
        ->check(CLI::IsMember(configuration_names()));
    app.add_option("--threads", thread_counts, "thread counts (default: 1 and all)")->delimiter(',');
    app.add_flag("!--no-embree", embree, "leave out Embree's builds");
    CLI11_PARSE(app, argc, argv);

    try {
        uint32_t all_threads = std::max(1u, std::thread::hardware_concurrency());
        if (thread_counts.empty()) {
            thread_counts.push_back(1);
            if (all_threads > 1) thread_counts.push_back(all_threads);
        }

        nlohmann::json result = prism::bench::result_header();
        result["benchmark"] = "bvh_build";
        result["runs"] = runs;
        result["layout"] = "stack (sah, median), wide (sah-wide)";
        result["max_leaf_size"] = prism::BvhBuildOptions{}.max_leaf_size;
        result["bins"] = prism::BvhBuildOptions{}.bins;
        result["configurations"] = {
            {"sah", "binned SAH, 16 bins, stack layout: tree + flattening + SAH cost"},
            {"sah-wide",
             "binned SAH, 32 bins, wide layout (the cpu backend's static scenes): tree + flattening + "
             "8-wide collapse + SAH cost"},
            {"sah-32bins", "as sah with 32 bins"},
            {"median", "the seed's median split, stack layout"},
            {"embree-commit-<quality>", "rtcCommitScene of one triangle geometry at that RTCBuildQuality"},
            {"embree-binary-<quality>",
             "rtcBuildBVH, branching 2, leaves <= 4, SAH block 1, costs 1/1; sah_cost() "
             "of the tree"},
            {"embree-binary-<quality>-block4", "as embree-binary with SAH block size 4 (as sah-wide counts leaves)"}};
        double load[3] = {0, 0, 0};
        if (getloadavg(load, 3) == 3) result["load_average_at_start"] = {load[0], load[1], load[2]};
        result["results"] = nlohmann::json::array();
        result["skipped"] = nlohmann::json::array();
#ifdef PRISM_HAVE_EMBREE
        result["embree_version"] = prism::oracle::embree_version();
#endif

        std::printf("%-12s %9s %-22s %7s %11s %11s %9s %9s %9s %6s\n", "scene", "triangles", "method", "threads",
                    "build ms", "cpu ms", "Mtri/s", "SAH cost", "nodes", "depth");
        for (const auto& entry : kSeries) {
            if (!only.empty() && std::find(only.begin(), only.end(), entry.name) == only.end()) continue;
            fs::path path = fs::path(scenes_dir) / entry.file;
            if (!fs::exists(path)) {
                std::printf("%-12s skipped: %s not found\n", entry.name.c_str(), path.string().c_str());
                result["skipped"].push_back({{"scene", entry.name}, {"reason", "file not found"}});
                continue;
            }
            TriangleSoup soup = load_triangles(path);
            std::vector<Aabb> bounds = triangle_bounds(soup);
            if (bounds.empty()) {
                std::printf("%-12s skipped: no loader for %s in this build\n", entry.name.c_str(),
                            path.filename().string().c_str());
                result["skipped"].push_back({{"scene", entry.name}, {"reason", "no loader in this build"}});
                continue;
            }
            for (const Configuration& configuration : kConfigurations) {
                if (!methods.empty() && std::find(methods.begin(), methods.end(), configuration.name) == methods.end())
                    continue;
                for (uint32_t threads : thread_counts) {
                    prism::BvhBuildOptions options;
                    options.method = configuration.method;
                    options.layout = configuration.layout;
                    options.bins = configuration.bins;
                    options.threads = threads;
                    std::vector<double> times, cpu_times;
                    std::vector<prism::BvhBuildPhases> phases;
                    prism::Bvh bvh;
                    for (int run = 0; run < runs; ++run) {
                        std::clock_t cpu_start = std::clock();
                        bvh = prism::build_bvh(bounds, options);
                        cpu_times.push_back(cpu_ms_since(cpu_start));
                        times.push_back(bvh.build_ms);
                        phases.push_back(bvh.phases);
                    }
                    report(result["results"], entry.name, entry.file, bounds.size(), configuration.name, threads, times,
                           cpu_times, &bvh);
                    result["results"].back()["phase_ms_median"] = phase_medians(phases);
                }
            }
#ifdef PRISM_HAVE_EMBREE
            if (!embree) continue;
            using prism::oracle::EmbreeQuality;
            for (uint32_t threads : thread_counts) {
                prism::oracle::EmbreeBuilder builder(threads);
                prism::oracle::TriangleSoupView view{soup.positions, soup.triangles};
                builder.commit_ms(view, EmbreeQuality::Medium);  // warm-up: Embree starts its threads on first use
                for (EmbreeQuality quality : {EmbreeQuality::Medium, EmbreeQuality::High}) {
                    std::vector<double> times, cpu_times;
                    for (int run = 0; run < runs; ++run) {
                        std::clock_t cpu_start = std::clock();
                        times.push_back(builder.commit_ms(view, quality));
                        cpu_times.push_back(cpu_ms_since(cpu_start));
                    }
                    report(result["results"], entry.name, entry.file, bounds.size(),
                           std::string("embree-commit-") + prism::oracle::embree_quality_name(quality), threads, times,
                           cpu_times, nullptr);
                }
                for (uint32_t block : {1u, 4u}) {
                    std::vector<double> times;
                    prism::Bvh bvh;
                    for (int run = 0; run < runs; ++run) {
                        bvh = builder.build_binary(bounds, EmbreeQuality::Medium, 4, block);
                        times.push_back(bvh.build_ms);
                    }
                    report(result["results"], entry.name, entry.file, bounds.size(),
                           std::string("embree-binary-medium") + (block == 4 ? "-block4" : ""), threads, times, {},
                           &bvh);
                }
            }
#else
            (void)embree;
#endif
        }
        prism::bench::write_result(out, result);
    } catch (const prism::Error& error) {
        std::fprintf(stderr, "bvh_build_bench: %s\n", error.what());
        return 1;
    }
    return 0;
}
