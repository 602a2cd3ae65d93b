#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sys/wait.h>

namespace prism::test {

std::filesystem::path scenes_dir() {
    if (const char* dir = std::getenv("PRISM_SCENES_DIR")) return dir;
    return PRISM_SCENES_DIR;
}

std::filesystem::path scene(const std::string& relative) { return scenes_dir() / relative; }

std::filesystem::path temp_dir(const std::string& name) {
    std::filesystem::path base = std::getenv("PRISM_TEST_TMP") ? std::getenv("PRISM_TEST_TMP")
                                                                : std::filesystem::temp_directory_path() / "prism";
    std::filesystem::path dir = base / name;
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
    std::filesystem::path path = temp_dir("files") / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

CommandResult run_prism(const std::string& arguments) {
    CommandResult result;
    std::string command = std::string("'") + PRISM_BINARY + "' " + arguments + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    int status = pclose(pipe);
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status)) result.exit_code = 128 + WTERMSIG(status);
    return result;
}

}  // namespace prism::test
