// Options every scene-reading subcommand shares (--scene, --data-dir, --bvh, --bvh-layout) and the loading
// step with its timings.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "core/device_scene.h"
#include "core/scene.h"

namespace prism::app {

struct SceneOptions {
    std::string scene = "builtin:sphere";
    std::string data_dir = "../shared/scenes";
    std::string bvh = "sah";
    std::string layout = "stack";
};

void add_scene_options(CLI::App* command, SceneOptions& options, bool scene_required = false);

struct LoadedScene {
    Scene scene;
    DeviceScene device;
    double load_ms = 0.0;
};

LoadedScene load_and_build(const SceneOptions& options);

}  // namespace prism::app
