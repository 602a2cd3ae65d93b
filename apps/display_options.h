// How the frame's light becomes the picture, for the commands that show or write one (`render`, `view`):
// --exposure and --tone-map (docs/cli.md).
#pragma once

#include <CLI/CLI.hpp>

#include "core/render/renderer.h"

namespace prism::app {

void add_display_options(CLI::App* command, RenderSettings& settings);

}  // namespace prism::app
