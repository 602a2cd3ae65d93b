#include "bench/bandwidth/bandwidth.h"

#include <cstdio>

#include "bench/bandwidth/api_runners.h"
#include "bench/bandwidth/report.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bench_json.h"
#include "core/error.h"

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

}  // namespace

void run_bandwidth(const Options& options) {
    Report report{make_plan(options), {}};
    std::vector<std::string> apis = options.apis;
    if (apis.empty()) apis.assign(std::begin(known_apis), std::end(known_apis));
    for (const std::string& api : apis)
        if (!known_api(api)) throw Error("--api: unknown API '" + api + "' (use cuda, opencl, vulkan)");

    for (const std::string& api : apis) {
        std::fprintf(stderr, "measuring %s...\n", api.c_str());
        report.apis.push_back(measure(api, report.plan));
    }
    print_report(report, stdout);
    if (!options.json_path.empty()) bench::write_result(options.json_path, report_json(report));
    if (!options.plot_path.empty()) {
        write_plot(report, options.plot_path);
        std::printf("wrote %s\n", options.plot_path.c_str());
    }
}

}  // namespace prism::bandwidth
