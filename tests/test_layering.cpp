// The architecture as a rule the build checks (docs/architecture.md, "Layers and dependencies"): each folder of
// core/ includes only the folders below it, core/ includes no GPU API header, and kernels/ includes nothing
// outside itself, so the single source compiles unchanged as C++, CUDA, OpenCL C and GLSL.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "core/util/environment.h"

namespace {

namespace fs = std::filesystem;

// Every `#include "..."` and `#include <...>` of a file.
std::vector<std::string> includes_of(const fs::path& file) {
    static const std::regex include(R"(^\s*#\s*include\s*["<]([^">]+)[">])");
    std::vector<std::string> found;
    std::ifstream in(file);
    std::string line;
    std::smatch match;
    while (std::getline(in, line))
        if (std::regex_search(line, match, include)) found.push_back(match[1]);
    return found;
}

std::vector<fs::path> sources_under(const fs::path& dir) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (entry.is_regular_file() && (entry.path().extension() == ".h" || entry.path().extension() == ".cpp"))
            files.push_back(entry.path());
    return files;
}

const fs::path kSource = PRISM_SOURCE_DIR;

TEST(Layering, CoreFoldersIncludeOnlyTheFoldersBelowThem) {
    const std::map<std::string, std::set<std::string>> allowed = {
        {"util", {"util"}},
        {"scene", {"scene", "util"}},
        {"image", {"image", "scene", "util"}},
        {"loaders", {"loaders", "image", "scene", "util"}},
        {"bvh", {"bvh", "util"}},
        {"render", {"render", "bvh", "loaders", "image", "scene", "util"}},
    };
    size_t files = 0;
    for (const fs::path& file : sources_under(kSource / "core")) {
        fs::path relative = fs::relative(file, kSource / "core");
        ASSERT_GT(std::distance(relative.begin(), relative.end()), 1) << "core/" << relative << " is outside a folder";
        std::string folder = relative.begin()->string();
        ASSERT_TRUE(allowed.count(folder)) << "core/" << folder << "/ is not in the layering rule";
        ++files;
        for (const std::string& included : includes_of(file)) {
            if (included.rfind("core/", 0) != 0) continue;
            std::string target = included.substr(5, included.find('/', 5) - 5);
            EXPECT_TRUE(allowed.at(folder).count(target)) << "core/" << relative.string() << " includes " << included;
        }
    }
    EXPECT_GT(files, 50u);
}

TEST(Layering, CoreIncludesNoGpuApiAndKernelsNothingOutside) {
    for (const fs::path& file : sources_under(kSource / "core"))
        for (const std::string& included : includes_of(file))
            for (const char* api : {"cuda", "CL/", "vulkan/", "GL/", "GLFW/", "backends/", "viewer/", "apps/"})
                EXPECT_NE(included.rfind(api, 0), 0u) << file << " includes " << included;
    for (const fs::path& file : sources_under(kSource / "kernels"))
        for (const std::string& included : includes_of(file))
            for (const char* outside : {"core/", "backends/", "viewer/", "apps/", "shaders/"})
                EXPECT_NE(included.rfind(outside, 0), 0u) << file << " includes " << included;
}

// PRISM_* variables are read in one place (core/util/environment.cpp), from its table, so each has a name users
// can look up (docs/environment.md) and a typo in the code cannot invent a new one.
TEST(Layering, PrismVariablesAreReadOnlyThroughTheSettingsTable) {
    static const std::regex direct(R"(getenv\(\s*"PRISM_)");
    for (const char* folder : {"core", "apps", "backends", "viewer", "bench"})
        for (const fs::path& file : sources_under(kSource / folder)) {
            std::ifstream in(file);
            std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            EXPECT_FALSE(std::regex_search(text, direct)) << file << " reads a PRISM_ variable with getenv";
        }
    std::ifstream doc(kSource / "docs" / "environment.md");
    std::string listed((std::istreambuf_iterator<char>(doc)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(listed.empty()) << "docs/environment.md is missing";
    for (const prism::SettingInfo& info : prism::settings())
        EXPECT_NE(listed.find(std::string("`") + info.name + "`"), std::string::npos)
            << info.name << " is not documented";
}

}  // namespace
