#include "bench/bandwidth/bandwidth.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "bench/bandwidth/api_runners.h"
#include "bench/bandwidth/report.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bench_json.h"
#include "bench/plot_script.h"
#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism::bandwidth {
namespace {

const char* const known_apis[] = {"cuda", "opencl", "vulkan"};

bool known_api(const std::string& api) {
    for (const char* known : known_apis)
        if (api == known) return true;
    return false;
}

// Each API is compiled in only when its toolkit was found at configure time.
ApiResult measure(const std::string& api, const Plan& plan) {
#ifdef PRISM_BANDWIDTH_CUDA
    if (api == "cuda") return measure_cuda(plan);
#endif
#ifdef PRISM_BANDWIDTH_OPENCL
    if (api == "opencl") return measure_opencl(plan);
#endif
#ifdef PRISM_BANDWIDTH_VULKAN
    if (api == "vulkan") return measure_vulkan(plan);
#endif
    return ApiResult{api, "not built into this prism (its toolkit was missing or disabled at configure time)", {}};
}

Plan make_plan(const Options& options) {
    Plan plan;
    plan.sizes = options.sizes.empty() ? default_sizes() : parse_sizes(options.sizes);
    if (options.repeats < 1) throw Error("--repeats: must be at least 1");
    if (options.warmup < 0) throw Error("--warmup: must not be negative");
    plan.repeats = options.repeats;
    plan.warmup = options.warmup;
    std::string staging =
        setting_choice(Setting::VulkanStaging, {"uncached", "cached", "host", "host-4k"}, "prism bandwidth");
    if (!staging.empty()) plan.vulkan_staging = staging;
    if (std::optional<std::string> regions = setting(Setting::VulkanCopyRegions); regions && !regions->empty()) {
        unsigned value = 0;
        auto [end, error] = std::from_chars(regions->data(), regions->data() + regions->size(), value);
        if (error != std::errc() || end != regions->data() + regions->size() || value < 1 || value > 64)
            throw Error(std::string("prism bandwidth: ") + setting_name(Setting::VulkanCopyRegions) + "='" +
                        shorten(*regions) + "' is not a whole number from 1 to 64");
        plan.vulkan_copy_regions = value;
    }
    for (const std::string& filter : options.devices) {
        size_t colon = filter.find(':');
        DeviceFilter parsed;
        if (colon != std::string::npos && known_api(filter.substr(0, colon))) {
            parsed.api = filter.substr(0, colon);
            parsed.substring = filter.substr(colon + 1);
        } else {
            parsed.substring = filter;
        }
        plan.filters.push_back(parsed);
    }
    return plan;
}

// The chart is drawn from the JSON: the --json file, or a temporary one when only --plot was asked for.
void write_plot(const nlohmann::json& result, const Options& options) {
    std::filesystem::path json_path = options.json_path;
    bool temporary = json_path.empty();
    if (temporary) {
        json_path = std::filesystem::temp_directory_path() / ("prism-bandwidth-" + std::to_string(getpid()) + ".json");
        std::ofstream out(json_path);
        out << result.dump(2) << "\n";
        if (!out) throw file_error(json_path.string(), "cannot write the JSON to plot");
    }
    try {
        bench::run_plot_script({json_path}, options.plot_path, "--plot");
    } catch (...) {
        if (temporary) std::filesystem::remove(json_path);
        throw;
    }
    if (temporary) std::filesystem::remove(json_path);
    std::printf("wrote %s\n", options.plot_path.c_str());
}

}  // namespace

void run_bandwidth(const Options& options) {
    Report report{make_plan(options), {}};
    std::vector<std::string> apis = options.apis;
    if (apis.empty()) apis.assign(std::begin(known_apis), std::end(known_apis));
    for (const std::string& api : apis)
        if (!known_api(api)) throw Error("--api: unknown API '" + api + "' (use cuda, opencl, vulkan)");
    if (!options.plot_path.empty()) {
        std::string extension = std::filesystem::path(options.plot_path).extension().string();
        if (extension != ".png" && extension != ".PNG")
            throw Error("--plot: expected a .png file name, got '" + options.plot_path + "'");
        bench::require_plotting("--plot");  // before measuring, so a missing matplotlib costs no time
    }

    for (const std::string& api : apis) {
        std::fprintf(stderr, "measuring %s...\n", api.c_str());
        report.apis.push_back(measure(api, report.plan));
    }
    print_report(report, stdout);
    nlohmann::json result = report_json(report);
    if (!options.json_path.empty()) bench::write_result(options.json_path, result);
    if (!options.plot_path.empty()) write_plot(result, options);
}

}  // namespace prism::bandwidth
