// Each subcommand of `prism` lives in its own cmd_<name>.cpp and adds itself to the CLI here.
#pragma once

#include <CLI/CLI.hpp>

namespace prism::app {

void add_render_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_rays_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_bandwidth_command(CLI::App& app);
void add_view_command(CLI::App& app);

}  // namespace prism::app
