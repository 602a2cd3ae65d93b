// `prism`: render, view, bench, bandwidth, rays, info. Every error the user can cause arrives here as one
// exception and leaves as one line on stderr with exit code 1; command-line usage errors leave with exit code 2
// (apps/cli_conventions.h).
#include <cstdio>
#include <exception>
#include <new>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "backends/backend_list.h"
#include "core/util/error.h"

int main(int argc, char** argv) {
    prism::register_builtin_backends();
    CLI::App app{"Prism: one ray-tracing source, four compute APIs (CPU, CUDA, OpenCL, Vulkan)", "prism"};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Show help for every subcommand");
    prism::app::add_global_options(app);
    prism::app::add_render_command(app);
    prism::app::add_info_command(app);
    prism::app::add_rays_command(app);
    prism::app::add_bench_command(app);
    prism::app::add_bandwidth_command(app);
    prism::app::add_view_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return prism::app::report_parse_error(app, e);
    } catch (const prism::Error& e) {
        std::fprintf(stderr, "prism: error: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "prism: error: out of host memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "prism: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
