// The commit and build type baked in at configure time, for result files and `prism info`.
#pragma once

namespace prism {
const char* build_commit();
const char* build_type();
}  // namespace prism
