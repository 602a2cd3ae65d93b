// `prism bench`: the seed's results table (thesis Tables 2/3) redone per backend and scene — frame time, fps,
// per-stage device times and Mrays/s per ray type (primary, secondary by depth, shadow), median of N runs after
// warm-up — and, with --embree, ray-query throughput of each backend against Embree on the same rays (the methods
// interleaved round by round).
// Every backend traces the same rays: frames are deterministic, and the ray counts per depth are checked equal.
// A backend or scene that fails is recorded with its error and the others still run: the JSON of every finished run
// is written, and only then does the command fail.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>

#include <nlohmann/json.hpp>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/frame_report.h"
#include "apps/option_checks.h"
#include "apps/progress.h"
#include "apps/scene_options.h"
#include "bench/bench_json.h"
#include "core/util/error.h"
#include "core/util/median.h"
#include "core/image/image_compare.h"
#include "core/render/render_engine.h"
#ifdef PRISM_HAVE_EMBREE
#include <embree3/rtcore_config.h>

#include "bench/embree_oracle.h"
#endif

namespace prism::app {
namespace {

struct BenchOptions {
    SceneOptions scene;
    std::string scenes = "builtin:sphere,builtin:bunny,builtin:dragon";
    std::string backends = "cpu";
    RenderSettings settings;
    bool seed_setting = false;
    uint32_t runs = 10;
    uint32_t warmup = 2;
    bool embree = false;
    uint32_t query_rays = 1000000;
    std::string json;
};

// Median over runs of each stage's time at each depth.
struct StageMedians {
    std::vector<std::vector<std::vector<double>>> samples;  // [stage][depth][run]
    StageMedians() : samples(stage_count, std::vector<std::vector<double>>(RT_MAX_DEPTH + 1)) {}
    void add(const FrameStats& stats) {
        std::vector<std::vector<double>> frame(stage_count, std::vector<double>(RT_MAX_DEPTH + 1, 0.0));
        for (const StageTiming& t : stats.stages) frame[size_t(t.stage)][t.depth] += t.milliseconds;
        for (size_t s = 0; s < stage_count; ++s)
            for (size_t d = 0; d <= RT_MAX_DEPTH; ++d) samples[s][d].push_back(frame[s][d]);
    }
    double at(Stage stage, uint32_t depth) const { return median(samples[size_t(stage)][depth]); }
    double total(Stage stage) const {
        double sum = 0.0;
        for (uint32_t d = 0; d <= RT_MAX_DEPTH; ++d) sum += at(stage, d);
        return sum;
    }
};

double mrays(uint64_t rays, double ms) { return ms > 0.0 ? double(rays) / (ms * 1e3) : 0.0; }

// The first backend's frame: the others report how closely they traced the same rays and made the same image.
struct FirstFrame {
    std::vector<uint32_t> rays_per_depth;
    std::vector<uint32_t> image;
};

// One line of what the traversal and shading stages' kernels got from the API's compiler, where it says
// (registers per thread / private bytes per thread: stack and spills).
void print_kernel_resources(const nlohmann::json& resources) {
    std::string line;
    for (const nlohmann::json& stage : resources["stages"]) {
        const std::string name = stage["stage"].get<std::string>();
        if (name != "intersect" && name != "shadow" && name != "shade") continue;
        std::string registers = stage["registers"].is_null() ? "?" : std::to_string(stage["registers"].get<int>());
        std::string bytes =
            stage["private_bytes"].is_null() ? "?" : std::to_string(stage["private_bytes"].get<long long>());
        line += (line.empty() ? "" : ", ") + name + " " + registers + " / " + bytes + " B";
    }
    if (!line.empty())
        std::printf("  kernels (registers / private bytes per thread, %s): %s\n",
                    resources["source"].get<std::string>().c_str(), line.c_str());
}

nlohmann::json bench_frames(RenderEngine& engine, const Scene& scene, const BenchOptions& options, FirstFrame& first,
                            Progress& progress) {
    const uint32_t frames = options.warmup + options.runs;
    auto report = [&](uint32_t done) {
        progress.update(double(done) / frames,
                        done <= options.warmup
                            ? "warm-up " + std::to_string(done) + "/" + std::to_string(options.warmup)
                            : "run " + std::to_string(done - options.warmup) + "/" + std::to_string(options.runs));
    };
    for (uint32_t i = 0; i < options.warmup; ++i) {
        engine.render(scene.camera, options.settings);
        report(i + 1);
    }
    std::vector<double> frame_ms, enqueue_ms, wait_ms, readback_ms;
    StageMedians stages;
    FrameResult last;
    for (uint32_t i = 0; i < options.runs; ++i) {
        last = engine.render(scene.camera, options.settings);
        report(options.warmup + i + 1);
        frame_ms.push_back(last.stats.frame_ms);
        enqueue_ms.push_back(last.stats.enqueue_ms);
        wait_ms.push_back(last.stats.device_wait_ms);
        readback_ms.push_back(last.stats.readback_ms);
        stages.add(last.stats);
    }
    const FrameStats& s = last.stats;
    if (first.image.empty()) first = FirstFrame{s.rays_per_depth, last.image};
    // Same rays up to float rounding (a grazing ray may tip the other way under FMA contraction).
    double ray_difference = 0.0;
    for (size_t d = 0; d < std::min(first.rays_per_depth.size(), s.rays_per_depth.size()); ++d)
        ray_difference = std::max(ray_difference, std::abs(double(s.rays_per_depth[d]) - first.rays_per_depth[d]) /
                                                      std::max(1.0, double(first.rays_per_depth[d])));
    if (ray_difference > 1e-3 || first.rays_per_depth.size() != s.rays_per_depth.size())
        std::printf("  warning: %s traced %.3f%% different rays at some depth than the first backend\n",
                    engine.info().name.c_str(), 100.0 * ray_difference);

    nlohmann::json per_depth = nlohmann::json::array();
    uint64_t secondary = 0, shadows = 0;
    double secondary_ms = 0.0, shadow_ms = 0.0;
    // A depth's rays are traced by intersect, or for a scene of one instance in the stack layout by intersect_mesh
    // (kernels/stage_list.h); the other one is not launched or returns at once.
    auto intersect_ms_at = [&](uint32_t d) {
        return stages.at(Stage::Intersect, d) + stages.at(Stage::IntersectMesh, d);
    };
    for (uint32_t d = 0; d < s.rays_per_depth.size(); ++d) {
        double intersect_ms = intersect_ms_at(d);
        // A frame's shadow rays are traced by the shadow stage, or in scenes with cut-out or blended materials by
        // shadow_layers (kernels/stage_list.h); the other one is not launched or returns at once.
        double shadow_stage_ms = stages.at(Stage::Shadow, d) + stages.at(Stage::ShadowLayers, d);
        nlohmann::json row = {{"depth", d},
                              {"rays", s.rays_per_depth[d]},
                              {"shadow_rays", s.shadow_rays_per_depth[d]},
                              {"intersect_mrays_per_s", mrays(s.rays_per_depth[d], intersect_ms)},
                              {"shadow_mrays_per_s", mrays(s.shadow_rays_per_depth[d], shadow_stage_ms)}};
        for (size_t stage = 0; stage < stage_count; ++stage)  // <stage>_ms for every per-depth stage
            if (stage_pass(Stage(stage)) == StagePass::Bounce)
                row[std::string(stage_name(Stage(stage))) + "_ms"] = stages.at(Stage(stage), d);
        per_depth.push_back(std::move(row));
        if (d > 0) {
            secondary += s.rays_per_depth[d];
            secondary_ms += intersect_ms;
        }
        shadows += s.shadow_rays_per_depth[d];
        shadow_ms += shadow_stage_ms;
    }
    nlohmann::json stage_ms;
    for (size_t i = 0; i < stage_count; ++i) stage_ms[stage_name(Stage(i))] = stages.total(Stage(i));
    double frame = median(frame_ms);
    uint64_t primary = s.rays_per_depth.empty() ? 0 : s.rays_per_depth[0];
    return {{"frame_ms", frame},
            {"frame_ms_min", *std::min_element(frame_ms.begin(), frame_ms.end())},
            {"frame_ms_max", *std::max_element(frame_ms.begin(), frame_ms.end())},
            {"fps", 1000.0 / frame},
            {"stage_ms", stage_ms},
            {"host_ms",
             {{"enqueue", median(enqueue_ms)}, {"device_wait", median(wait_ms)}, {"readback", median(readback_ms)}}},
            {"total_rays", s.total_rays()},
            {"mrays_per_s_end_to_end", mrays(s.total_rays(), frame)},
            {"primary_mrays_per_s", mrays(primary, intersect_ms_at(0))},
            {"secondary_mrays_per_s", mrays(secondary, secondary_ms)},
            {"shadow_mrays_per_s", mrays(shadows, shadow_ms)},
            {"per_depth", per_depth},
            {"max_ray_count_difference_vs_first", ray_difference},
            {"image_psnr_vs_first_db", std::min(psnr_rgba8(first.image, last.image), 999.0)},  // 999: identical
            {"image_hash", std::hash<std::string_view>{}(std::string_view(
                               reinterpret_cast<const char*>(last.image.data()), last.image.size() * 4))}};
}

#ifdef PRISM_HAVE_EMBREE
// Ray-query throughput (closest hit) on the oracle rays, primary and diffuse measured separately. Every method —
// each backend, Embree rtcIntersect1 and rtcIntersect8 — runs once per round, round after round, so a machine
// that gets busier or quieter during the benchmark (a shared 2-core one) slows all of them alike; each reports
// its median round, after one warm-up round.
using QueryMethod = std::function<double(const std::vector<RayQuery>&)>;  // one run, in ms

std::vector<nlohmann::json> bench_queries(const std::vector<QueryMethod>& methods, const oracle::OracleRays& rays,
                                          uint32_t runs) {
    std::vector<RayQuery> primary(rays.rays.begin(), rays.rays.begin() + long(rays.primary));
    std::vector<RayQuery> diffuse(rays.rays.begin() + long(rays.primary), rays.rays.end());
    auto measure = [&](const std::vector<RayQuery>& set) {
        std::vector<std::vector<double>> ms(methods.size());
        for (uint32_t round = 0; round < runs + 1; ++round)
            for (size_t m = 0; m < methods.size(); ++m) {
                double t = methods[m](set);
                if (round > 0) ms[m].push_back(t);  // the first round is the warm-up
            }
        std::vector<double> medians;
        for (auto& samples : ms) medians.push_back(median(samples));
        return medians;
    };
    std::vector<double> primary_ms = measure(primary), diffuse_ms = measure(diffuse);
    std::vector<nlohmann::json> out;
    for (size_t m = 0; m < methods.size(); ++m)
        out.push_back({{"primary_rays", primary.size()},
                       {"diffuse_rays", diffuse.size()},
                       {"primary_ms", primary_ms[m]},
                       {"diffuse_ms", diffuse_ms[m]},
                       {"primary_mrays_per_s", mrays(primary.size(), primary_ms[m])},
                       {"diffuse_mrays_per_s", mrays(diffuse.size(), diffuse_ms[m])}});
    return out;
}
#endif

// A scene that did not load (no backend) or a backend that failed on a scene: the run goes on without it.
void record_failure(nlohmann::json& result, const std::string& scene, const std::string& backend,
                    const std::string& error) {
    nlohmann::json failure = {{"scene", scene}, {"error", error}};
    if (!backend.empty()) failure["backend"] = backend;
    result["failures"].push_back(failure);
    std::printf("  %s%s failed: %s\n", scene.c_str(), backend.empty() ? "" : (" on " + backend).c_str(), error.c_str());
    std::fflush(stdout);
}

void run_bench(BenchOptions options) {
    route_output(options.json);
    if (options.seed_setting) {
        // The seed framed each scene for about 100,000 intersections (thesis ch. 7): 400x250 primary rays.
        options.settings.width = 400;
        options.settings.height = 250;
    }
    if (options.runs == 0) throw Error("bench: --runs must be at least 1");
    for (const std::string& backend : comma_list(options.backends)) check_frame_options(backend, options.settings);
#ifndef PRISM_HAVE_EMBREE
    if (options.embree) throw Error("bench: --embree needs a build with Embree (apt-get install libembree-dev)");
#endif
    nlohmann::json result = bench::result_header();
    result["kind"] = "frames";
    result["settings"] = {{"width", options.settings.width},
                          {"height", options.settings.height},
                          {"max_depth", options.settings.max_depth},
                          {"runs", options.runs},
                          {"warmup", options.warmup},
                          {"seed_setting", options.seed_setting},
                          {"bvh", options.scene.bvh},
                          {"bvh_layout", options.scene.layout},
                          {"bvh_leaf_size", options.scene.bvh_leaf_size},
                          {"bvh_node_cost", options.scene.bvh_node_cost},
                          {"queries_interleaved", true}};
    result["scenes"] = nlohmann::json::array();
    result["failures"] = nlohmann::json::array();
    for (const std::string& scene_name : comma_list(options.scenes)) {
        SceneOptions scene_options = options.scene;
        scene_options.scene = scene_name;
        std::vector<std::string> backends = comma_list(options.backends);
        LoadedScene loaded;
        try {
            loaded = load_and_build(scene_options, backends.empty() ? "auto" : backends.front());
        } catch (const std::exception& e) {
            record_failure(result, scene_name, "", e.what());
            continue;
        }
        DeviceScenes device_scenes(loaded, scene_options);
        nlohmann::json scene_json = {{"scene", scene_name},
                                     {"triangles", loaded.device.traced_triangles},
                                     {"bvh_build_ms", loaded.device.bvh_build_ms},
                                     {"closed_solid_instances", loaded.device.closed_solid_instances},
                                     {"closed_solid_ms", loaded.device.closed_solid_ms},
                                     {"sah_cost", loaded.device.sah_cost},
                                     {"backends", nlohmann::json::array()}};
        FirstFrame first;
#ifdef PRISM_HAVE_EMBREE
        std::unique_ptr<oracle::EmbreeScene> embree;
        oracle::OracleRays rays;
        if (options.embree) {
            embree = std::make_unique<oracle::EmbreeScene>(loaded.scene);
            rays = oracle::make_oracle_rays(loaded.scene, *embree, options.query_rays / 2, options.query_rays, 7);
        }
#endif
        std::vector<std::unique_ptr<RenderEngine>> query_engines;  // kept for the interleaved query rounds
        for (const std::string& backend : backends) try {
                const DeviceScene& device = device_scenes.for_backend(backend);
                auto engine_owner = std::make_unique<RenderEngine>(backend, device);
                RenderEngine& engine = *engine_owner;
                BackendInfo info = engine.info();
                std::string layout = bvh_layout_name(device.bvh_options.layout);
                std::printf("%s on %s [%s], %s BVH...\n", scene_name.c_str(), backend.c_str(), info.device.c_str(),
                            layout.c_str());
                std::fflush(stdout);
                nlohmann::json entry = {{"backend", backend},
                                        {"api", info.name},
                                        {"device", info.device},
                                        {"driver", info.driver},
                                        {"api_version", info.api_version},
                                        {"bvh_layout", layout},
                                        {"bvh_build_ms", device.bvh_build_ms}};
                Progress progress("bench " + scene_name + " on " + backend);
                entry["frames"] = bench_frames(engine, loaded.scene, options, first, progress);
                progress.finish();
                entry["kernel_resources"] = bench::kernel_resources_json(engine.kernel_resources());
#ifdef PRISM_HAVE_EMBREE
                if (embree) query_engines.push_back(std::move(engine_owner));
#endif
                const auto& f = entry["frames"];
                std::printf("  frame %.2f ms (%.1f fps), primary %.1f, secondary %.1f, shadow %.1f Mrays/s\n",
                            f["frame_ms"].get<double>(), f["fps"].get<double>(), f["primary_mrays_per_s"].get<double>(),
                            f["secondary_mrays_per_s"].get<double>(), f["shadow_mrays_per_s"].get<double>());
                print_kernel_resources(entry["kernel_resources"]);
                scene_json["backends"].push_back(entry);
            } catch (const std::exception& e) {
                record_failure(result, scene_name, backend, e.what());
            }
#ifdef PRISM_HAVE_EMBREE
        if (embree) try {
                std::vector<QueryMethod> methods;
                for (auto& engine : query_engines)
                    methods.push_back([&engine](const std::vector<RayQuery>& set) {
                        engine->trace(set, false);
                        return engine->last_trace_ms();
                    });
                for (bool packets : {false, true})
                    methods.push_back([&embree, packets](const std::vector<RayQuery>& set) {
                        auto start = std::chrono::steady_clock::now();
                        if (packets)
                            embree->intersect8(set);
                        else
                            embree->intersect1(set);
                        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                            .count();
                    });
                std::vector<nlohmann::json> queries = bench_queries(methods, rays, options.runs);
                for (size_t b = 0; b < query_engines.size(); ++b) scene_json["backends"][b]["queries"] = queries[b];
                query_engines.clear();
                scene_json["embree"] = {{"version", RTC_VERSION_STRING},
                                        {"intersect1", queries[queries.size() - 2]},
                                        {"intersect8", queries.back()}};
                for (const auto& b : scene_json["backends"]) {
                    std::printf("  %s vs Embree rtcIntersect1: primary %.2fx, diffuse %.2fx\n",
                                b["backend"].get<std::string>().c_str(),
                                b["queries"]["primary_mrays_per_s"].get<double>() /
                                    scene_json["embree"]["intersect1"]["primary_mrays_per_s"].get<double>(),
                                b["queries"]["diffuse_mrays_per_s"].get<double>() /
                                    scene_json["embree"]["intersect1"]["diffuse_mrays_per_s"].get<double>());
                }
            } catch (const std::exception& e) {
                record_failure(result, scene_name, "embree queries", e.what());
            }
#endif
        result["scenes"].push_back(scene_json);
    }
    if (!options.json.empty()) bench::write_result(options.json, result);
    const nlohmann::json& failures = result["failures"];
    if (!failures.empty())
        throw Error("bench: " + std::to_string(failures.size()) + " run" + (failures.size() > 1 ? "s" : "") +
                    " failed (first: " + failures[0]["scene"].get<std::string>() +
                    (failures[0].contains("backend") ? " on " + failures[0]["backend"].get<std::string>() : "") + ": " +
                    failures[0]["error"].get<std::string>() + ")" +
                    (options.json.empty() ? "" : "; the finished runs and every error are in " + options.json));
}

}  // namespace

void add_bench_command(CLI::App& app) {
    auto options = std::make_shared<BenchOptions>();
    options->settings.width = 1920;
    options->settings.height = 1080;
    auto* command = app.add_subcommand("bench", "Frame times and Mrays/s per ray type, per backend and scene");
    command->add_option("--scenes", options->scenes, "comma-separated scenes")->capture_default_str();
    command->add_option("--backends", options->backends, "comma-separated backends")->capture_default_str();
    add_data_dir_option(command, options->scene.data_dir);
    command->add_option("--bvh", options->scene.bvh, "sah or median")->check(CLI::IsMember({"sah", "median"}));
    command
        ->add_option("--bvh-layout", options->scene.layout,
                     "stack, escape, wide or auto (per backend: wide on cpu, stack on GPUs; PRISM_BVH_LAYOUT "
                     "overrides auto)")
        ->check(CLI::IsMember({"stack", "escape", "wide", "auto"}))
        ->capture_default_str();
    add_bvh_shape_options(command, options->scene);
    command->add_option("--width", options->settings.width)->capture_default_str();
    command->add_option("--height", options->settings.height)->capture_default_str();
    command->add_option("--depth", options->settings.max_depth)->capture_default_str();
    command->add_flag("--seed-setting", options->seed_setting,
                      "the seed's setting: about 100,000 primary rays (400x250)");
    command->add_option("--runs", options->runs, "timed runs (median reported)")->capture_default_str();
    command->add_option("--warmup", options->warmup, "untimed runs first")->capture_default_str();
    command->add_flag("--embree", options->embree, "also ray queries against Embree (rtcIntersect1/8)");
    command->add_option("--query-rays", options->query_rays, "rays for --embree (half primary, half diffuse)")
        ->capture_default_str();
    add_json_option(command, options->json, "write results (bench/results/...), failures included");
    command->callback([options] { run_bench(*options); });
}

}  // namespace prism::app
