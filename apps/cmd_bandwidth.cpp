// `prism bandwidth`: the seed's bandwidth test (thesis Figure 8-1) across CUDA, OpenCL and Vulkan.
// The measuring lives in bench/bandwidth/ (prism_bench_lib); this file is the command line.
#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "core/util/error.h"

#ifdef PRISM_HAVE_BENCH_LIB
#include "bench/bandwidth/bandwidth.h"
#endif

namespace prism::app {

void add_bandwidth_command(CLI::App& app) {
#ifdef PRISM_HAVE_BENCH_LIB
    auto options = std::make_shared<bandwidth::Options>();
    auto* command = app.add_subcommand(
        "bandwidth",
        "Copy bandwidth on every CUDA, OpenCL and Vulkan device: H2D/D2H (pageable, pinned), D2D copy, D2D kernel");
    command->add_option("--sizes", options->sizes,
                        "Transfer sizes, comma-separated, with K/M/G suffixes (default 4K..1G in powers of 4)");
    command->add_option("--repeats", options->repeats, "Timed copies per measurement; the median is reported")
        ->capture_default_str();
    command->add_option("--warmup", options->warmup, "Untimed copies before each measurement")->capture_default_str();
    command->add_option("--api", options->apis, "APIs to measure: cuda,opencl,vulkan (default all)")->delimiter(',');
    command
        ->add_option("--device", options->devices,
                     "Device filters, e.g. opencl:nvidia or vulkan:llvmpipe or h100 (case-insensitive substring)")
        ->delimiter(',');
    add_json_option(command, options->json_path, "Write the results as JSON (schema in docs/bandwidth.md)");
    command->add_option("--plot", options->plot_path,
                        "Draw bandwidth against size into this PNG (bench/plot_bench.py; needs python3-matplotlib)");
    command->callback([options] {
        route_output(options->json_path);
        bandwidth::run_bandwidth(*options);
    });
#else
    auto* command = app.add_subcommand("bandwidth", "(not built: configure with PRISM_BENCH=ON)");
    command->callback([] { throw Error("prism bandwidth: not built (configure with -DPRISM_BENCH=ON)"); });
#endif
}

}  // namespace prism::app
