// Names of the screenshots P saves in an interactive session: prism-view-0001.png, -0002, ... in the working
// directory, the first number whose file does not exist yet, so a screenshot never overwrites anything (one from
// an earlier session included).
#pragma once

#include <filesystem>

namespace prism::viewer {

// Throws prism::Error when all 9999 names in `folder` are taken.
std::filesystem::path next_screenshot_path(const std::filesystem::path& folder = ".");

}  // namespace prism::viewer
