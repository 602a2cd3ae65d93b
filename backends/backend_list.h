#pragma once

namespace prism {
// Registers cpu and every GPU backend compiled into this build (see backends/CMakeLists.txt).
void register_builtin_backends();
}  // namespace prism
