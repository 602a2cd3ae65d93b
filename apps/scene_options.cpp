#include "apps/scene_options.h"

#include <chrono>

#include "core/scene_loader.h"

namespace prism::app {

void add_scene_options(CLI::App* command, SceneOptions& options, bool scene_required) {
    auto* scene = command->add_option("--scene", options.scene,
                                      "builtin:sphere|bunny|dragon, a Prism scene (.json) or a model "
                                      "(.gltf .glb .obj .ply .ply.gz)");
    if (scene_required) scene->required();
    else scene->capture_default_str();
    command->add_option("--data-dir", options.data_dir, "where builtin scenes find their assets")
        ->capture_default_str();
    command->add_option("--bvh", options.bvh, "BVH builder: sah (binned SAH) or median (the seed's split)")
        ->check(CLI::IsMember({"sah", "median"}))
        ->capture_default_str();
    command->add_option("--bvh-layout", options.layout, "node layout: stack or escape (the seed's stackless order)")
        ->check(CLI::IsMember({"stack", "escape"}))
        ->capture_default_str();
}

LoadedScene load_and_build(const SceneOptions& options) {
    LoadedScene loaded;
    auto start = std::chrono::steady_clock::now();
    LoadOptions load_options;
    load_options.data_dir = options.data_dir;
    loaded.scene = load_scene(options.scene, load_options);
    loaded.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    BvhBuildOptions bvh;
    bvh.method = options.bvh == "median" ? BvhMethod::Median : BvhMethod::BinnedSah;
    bvh.layout = options.layout == "escape" ? BvhLayout::Escape : BvhLayout::Stack;
    loaded.device = build_device_scene(loaded.scene, bvh);
    return loaded;
}

}  // namespace prism::app
