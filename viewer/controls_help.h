// Every control of `prism view`, as the help overlay (H or F1) lists it; docs/viewer.md has the same table.
#pragma once

#include <span>

namespace prism::viewer {

struct ControlHelp {
    const char* input;
    const char* action;
};

std::span<const ControlHelp> controls_help();

}  // namespace prism::viewer
