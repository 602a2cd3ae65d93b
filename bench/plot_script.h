// Charts are drawn by one program, bench/plot_bench.py (matplotlib), from the result JSON; C++ only finds and runs
// it. This is the lookup of the script and of a Python that can run it, shared by `prism bandwidth --plot` and the
// tests.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace prism::bench {

// The installed copy (<prefix>/share/prism/plot_bench.py beside <prefix>/bin/prism) when the running program has
// one, else the source tree's bench/plot_bench.py. Empty when neither exists.
std::filesystem::path plot_script_path();

// A Python 3 that imports matplotlib: $PRISM_PYTHON alone when it is set, else each python3 on PATH in order, then
// /usr/bin/python3 (a Python of a version manager earlier on PATH often lacks Debian's python3-matplotlib). Empty
// when none does.
std::filesystem::path plot_python();

// Checks that a chart can be drawn before any work is done: throws prism::Error naming `option`, the missing piece
// and exactly what to run.
void require_plotting(const std::string& option);

// Draws `results` (bench JSON files) into the PNG `out` with plot_bench.py; `baselines` are its --baseline files
// (the one-device renders that split renders are compared with). Throws prism::Error with the script's own one-line
// message when it fails.
void run_plot_script(const std::vector<std::filesystem::path>& results, const std::filesystem::path& out,
                     const std::string& option, const std::vector<std::filesystem::path>& baselines = {});

}  // namespace prism::bench
