#include "viewer/screenshot_names.h"

#include <cstdio>

#include "core/util/error.h"

namespace prism::viewer {

std::filesystem::path next_screenshot_path(const std::filesystem::path& folder) {
    for (int number = 1; number <= 9999; ++number) {
        char name[32];
        std::snprintf(name, sizeof name, "prism-view-%04d.png", number);
        std::filesystem::path path = folder / name;
        std::error_code error;
        if (!std::filesystem::exists(path, error) && !error) return path;
    }
    throw Error("view: " + (folder / "prism-view-NNNN.png").string() + ": all 9999 screenshot names are taken");
}

}  // namespace prism::viewer
