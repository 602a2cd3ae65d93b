#pragma once

namespace prism {
// Registers cpu and every GPU backend compiled into this build (see backends/CMakeLists.txt). Programs linked with
// Prism::prism have them registered before main() already; calling this again does nothing.
void register_builtin_backends();
}  // namespace prism
