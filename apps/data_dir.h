// Where builtin scenes (builtin:bunny, builtin:dragon) find their assets when --data-dir is not given, so they work
// from any folder: $PRISM_DATA_DIR; else the scenes folder found from the executable (in the build tree, the source
// tree's ../shared/scenes as recorded at configure time; in an install tree, <prefix>/share/prism/scenes); else
// ../shared/scenes from the current folder.
#pragma once

#include <filesystem>

namespace prism::app {

std::filesystem::path default_data_dir();

}  // namespace prism::app
