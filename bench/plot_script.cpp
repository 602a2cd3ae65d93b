#include "bench/plot_script.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include <sys/wait.h>
#include <unistd.h>

#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism::bench {
namespace {

const char* const kScriptName = "plot_bench.py";
const char* const kInstallAdvice =
    "run `sudo apt-get install python3-matplotlib` (scripts/install-deps.sh installs it)";

// For /bin/sh: the whole argument in single quotes, each ' written as '\''.
std::string shell_quote(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

bool executable(const std::filesystem::path& path) {
    std::error_code error;
    return std::filesystem::is_regular_file(path, error) && access(path.c_str(), X_OK) == 0;
}

bool imports_matplotlib(const std::filesystem::path& python) {
    std::string command = shell_quote(python.string()) + " -c 'import matplotlib' >/dev/null 2>&1";
    return std::system(command.c_str()) == 0;
}

std::filesystem::path find_plot_python() {
    if (std::optional<std::string> chosen = setting(Setting::Python)) {
        if (executable(*chosen) && imports_matplotlib(*chosen)) return *chosen;
        return {};
    }
    std::vector<std::filesystem::path> candidates;
    std::stringstream path(std::getenv("PATH") ? std::getenv("PATH") : "");
    for (std::string folder; std::getline(path, folder, ':');)
        if (!folder.empty()) candidates.push_back(std::filesystem::path(folder) / "python3");
    candidates.emplace_back("/usr/bin/python3");
    for (const std::filesystem::path& python : candidates)
        if (executable(python) && imports_matplotlib(python)) return python;
    return {};
}

}  // namespace

std::filesystem::path plot_script_path() {
    std::error_code error;
    std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) {
        // The install rule in bench/CMakeLists.txt puts the script at <prefix>/share/prism.
        std::filesystem::path installed = program.parent_path().parent_path() / "share" / "prism" / kScriptName;
        if (std::filesystem::is_regular_file(installed, error)) return installed;
    }
    std::filesystem::path source = std::filesystem::path(PRISM_SOURCE_DIR) / "bench" / kScriptName;
    if (std::filesystem::is_regular_file(source, error)) return source;
    return {};
}

std::filesystem::path plot_python() {
    // Each probe starts a Python; remember the answer for the environment it was found in.
    static std::map<std::string, std::filesystem::path> found;
    std::optional<std::string> chosen = setting(Setting::Python);
    const char* path = std::getenv("PATH");
    std::string key = chosen.value_or("\n") + '\0' + (path ? path : "");
    auto cached = found.find(key);
    if (cached == found.end()) cached = found.emplace(key, find_plot_python()).first;
    return cached->second;
}

void require_plotting(const std::string& option) {
    if (plot_script_path().empty())
        throw Error(option + ": " + kScriptName + " is neither installed beside this prism (../share/prism/) nor in " +
                    "its source tree (" + PRISM_SOURCE_DIR + "/bench/)");
    if (plot_python().empty()) {
        std::optional<std::string> chosen = setting(Setting::Python);
        std::string tried = chosen ? "PRISM_PYTHON=" + *chosen : "python3 on PATH and /usr/bin/python3";
        throw Error(option + ": no Python 3 with matplotlib (tried " + tried + "): " + kInstallAdvice);
    }
}

void run_plot_script(const std::vector<std::filesystem::path>& results, const std::filesystem::path& out,
                     const std::string& option, const std::vector<std::filesystem::path>& baselines) {
    require_plotting(option);
    std::string command = shell_quote(plot_python().string()) + " " + shell_quote(plot_script_path().string());
    // Appended piece by piece: GCC 12 at -O3 warns (-Wrestrict, falsely) on `literal + std::string` here.
    for (const std::filesystem::path& result : results) command.append(" ").append(shell_quote(result.string()));
    for (const std::filesystem::path& baseline : baselines)
        command.append(" --baseline ").append(shell_quote(baseline.string()));
    command.append(" --out ").append(shell_quote(out.string())).append(" 2>&1");
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) throw Error(option + ": cannot start " + plot_python().string());
    std::string output;
    std::array<char, 4096> buffer;
    while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
    int status = pclose(pipe);
    if (status != 0) {
        // The script's last line is its one-line error.
        while (!output.empty() && output.back() == '\n') output.pop_back();
        size_t newline = output.find_last_of('\n');
        std::string last = newline == std::string::npos ? output : output.substr(newline + 1);
        if (last.empty()) {
            int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
            last = std::string(kScriptName) + " failed (exit " + std::to_string(code) + ")";
        }
        throw Error(option + ": " + last);
    }
}

}  // namespace prism::bench
