#include "apps/data_dir.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>

#include "core/util/environment.h"

namespace prism::app {
namespace {

std::filesystem::path executable_folder() {
    std::error_code error;
    std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
    return error ? std::filesystem::path() : executable.parent_path();
}

bool inside(const std::filesystem::path& path, const std::filesystem::path& folder) {
    std::error_code error;
    std::filesystem::path canonical_folder = std::filesystem::weakly_canonical(folder, error);
    if (error || canonical_folder.empty()) return false;
    auto mismatch = std::mismatch(canonical_folder.begin(), canonical_folder.end(), path.begin(), path.end());
    return mismatch.first == canonical_folder.end();
}

// The scenes folder that belongs to this executable, or empty when it has none.
std::filesystem::path scenes_beside_executable() {
    std::filesystem::path folder = executable_folder();
    if (folder.empty()) return {};
    std::error_code error;
    // A binary still in its build tree reads the scenes of the checkout it was built from.
    if (inside(folder, PRISM_BUILD_TREE) && std::filesystem::is_directory(PRISM_SOURCE_SCENES_DIR, error))
        return PRISM_SOURCE_SCENES_DIR;
    std::filesystem::path installed = folder.parent_path() / "share" / "prism" / "scenes";  // <prefix>/bin/prism
    if (std::filesystem::is_directory(installed, error)) return installed;
    return {};
}

}  // namespace

std::filesystem::path default_data_dir() {
    if (std::string variable = setting(Setting::DataDir).value_or(""); !variable.empty()) return variable;
    std::filesystem::path found = scenes_beside_executable();
    return found.empty() ? std::filesystem::path("../shared/scenes") : found;
}

}  // namespace prism::app
