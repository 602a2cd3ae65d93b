// Options every scene-reading subcommand shares (--scene, --data-dir, --bvh, --bvh-layout) and the loading
// step with its timings.
#pragma once

#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "core/render/device_scene.h"
#include "core/scene/scene.h"

namespace prism::app {

struct SceneOptions {
    std::string scene = "builtin:sphere";
    std::string data_dir;  // empty: default_data_dir() (apps/data_dir.h)
    std::string bvh = "sah";
    std::string layout = "auto";  // stack, escape, wide, or auto: per backend (core/render/render_engine.h)
    // The SAH build's leaf bound and node cost (BvhBuildOptions): --bvh-leaf-size, --bvh-node-cost.
    uint32_t bvh_leaf_size = BvhBuildOptions{}.max_leaf_size;
    float bvh_node_cost = BvhBuildOptions{}.traversal_cost;
    // Instances may move after the build (the viewer's moving object): the wide layout then keeps its top level
    // over instances, which a move refits; otherwise it flattens them into one BVH (BvhBuildOptions).
    bool moving_instances = false;
    bool allow_any_path = false;  // --allow-any-path: the scene may read files outside its folder
    std::string animation;        // --animation: a glTF scene's animation to play (empty: the first)
};

void add_scene_options(CLI::App* command, SceneOptions& options, bool scene_required = false);
// --bvh-leaf-size and --bvh-node-cost (in add_scene_options; prism bench adds them on their own).
void add_bvh_shape_options(CLI::App* command, SceneOptions& options);
// --data-dir alone (for commands that take several scenes).
CLI::Option* add_data_dir_option(CLI::App* command, std::string& data_dir);

struct LoadedScene {
    Scene scene;
    DeviceScene device;
    double load_ms = 0.0;
    std::string layout;  // the node layout built (options.layout resolved for the backend)
};

// Loads the scene and builds its device arrays with the BVH layout `options.layout` resolves to for `backend`,
// showing the progress of both steps (apps/progress.h).
LoadedScene load_and_build(const SceneOptions& options, const std::string& backend = "auto");
DeviceScene build_device_scene_for(const Scene& scene, const SceneOptions& options, BvhLayout layout,
                                   const BvhProgress& progress = {});

// A loaded scene's device arrays for each backend: the layout `options.layout` resolves to for it (auto: wide on
// cpu, stack on GPUs), built once per layout; the first build serves every backend that wants its layout.
class DeviceScenes {
public:
    DeviceScenes(const LoadedScene& loaded, const SceneOptions& options) : loaded_(loaded), options_(options) {}
    const DeviceScene& for_backend(const std::string& backend);

private:
    const LoadedScene& loaded_;
    SceneOptions options_;
    std::map<BvhLayout, DeviceScene> other_layouts_;
};

}  // namespace prism::app
