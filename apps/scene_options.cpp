#include "apps/scene_options.h"

#include <chrono>
#include <cstdlib>
#include <new>

#include "apps/data_dir.h"
#include "apps/progress.h"

#include "apps/option_checks.h"
#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"

namespace prism::app {

void add_scene_options(CLI::App* command, SceneOptions& options, bool scene_required) {
    auto* scene = command->add_option("--scene", options.scene,
                                      "builtin:sphere|bunny|dragon, a Prism scene (.json) or a model "
                                      "(.gltf .glb .obj .ply .ply.gz)");
    if (scene_required)
        scene->required();
    else
        scene->capture_default_str();
    add_data_dir_option(command, options.data_dir);
    command->add_option("--bvh", options.bvh, "BVH builder: sah (binned SAH) or median (the seed's split)")
        ->check(CLI::IsMember({"sah", "median"}))
        ->capture_default_str();
    command
        ->add_option("--bvh-layout", options.layout,
                     "node layout: stack, escape (the seed's stackless order), wide (8-wide nodes) or auto (wide on "
                     "cpu/cpu-ref, stack on GPUs; PRISM_BVH_LAYOUT overrides auto)")
        ->check(CLI::IsMember({"stack", "escape", "wide", "auto"}))
        ->capture_default_str();
    add_bvh_shape_options(command, options);
    command->add_flag("--allow-any-path", options.allow_any_path,
                      "let the scene read files outside its own folder (absolute or ../ URIs and paths)");
    command->add_option("--animation", options.animation,
                        "which animation of a glTF scene sequences and the viewer play: its index, its name, or all "
                        "(default: the first)");
}

void add_bvh_shape_options(CLI::App* command, SceneOptions& options) {
    command
        ->add_option("--bvh-leaf-size", options.bvh_leaf_size,
                     "most triangles in a BVH leaf (1-" + std::to_string(RT_WIDE_LEAF_MAX) +
                         "); the SAH splits smaller leaves where that costs less")
        ->check(CLI::Range(1u, RT_WIDE_LEAF_MAX))
        ->capture_default_str();
    command
        ->add_option("--bvh-node-cost", options.bvh_node_cost,
                     "the SAH's cost of visiting a node, in triangle tests (0.1-100): higher gives fuller leaves")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                char* end = nullptr;
                float cost = std::strtof(text.c_str(), &end);
                bool whole = end && *end == '\0' && end != text.c_str();
                return whole && cost >= 0.1f && cost <= 100.0f ? ""
                                                               : "Value " + text + " is not a number from 0.1 to 100";
            },
            "0.1-100"))
        ->capture_default_str();
}

CLI::Option* add_data_dir_option(CLI::App* command, std::string& data_dir) {
    return command->add_option("--data-dir", data_dir,
                               "where builtin scenes find their assets (default: $PRISM_DATA_DIR, else the scenes "
                               "folder of this build or install, else ../shared/scenes)");
}

DeviceScene build_device_scene_for(const Scene& scene, const SceneOptions& options, BvhLayout layout,
                                   const BvhProgress& progress) {
    BvhBuildOptions bvh;
    bvh.method = options.bvh == "median" ? BvhMethod::Median : BvhMethod::BinnedSah;
    bvh.layout = layout;
    bvh.max_leaf_size = options.bvh_leaf_size;
    bvh.traversal_cost = options.bvh_node_cost;
    bvh.flatten_instances = !options.moving_instances;
    return build_device_scene(scene, bvh, progress);
}

LoadedScene load_and_build(const SceneOptions& options, const std::string& backend) {
    LoadedScene loaded;
    check_backend_option(backend);  // every scene-reading command: cpu:7 fails before loading
    BvhLayout layout = resolve_bvh_layout(options.layout, backend);  // a bad PRISM_BVH_LAYOUT fails before loading
    auto start = std::chrono::steady_clock::now();
    LoadOptions load_options;
    load_options.data_dir = options.data_dir.empty() ? default_data_dir() : std::filesystem::path(options.data_dir);
    Progress loading("loading " + options.scene);
    load_options.allow_any_path = options.allow_any_path;
    load_options.animation = options.animation;
    load_options.progress = [&loading](double fraction) { loading.update(fraction); };
    loaded.scene = load_scene(options.scene, load_options);
    loading.finish();
    loaded.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    Progress building("building the " + bvh_layout_name(layout) + " BVH of " + options.scene);
    try {
        loaded.device = build_device_scene_for(loaded.scene, options, layout, [&building](double fraction) {
            building.update(fraction, "triangles in leaves");
        });
    } catch (const std::bad_alloc&) {
        throw Error(options.scene + ": out of host memory while building the BVH and device arrays");
    }
    building.finish();
    loaded.layout = bvh_layout_name(layout);
    return loaded;
}

const DeviceScene& DeviceScenes::for_backend(const std::string& backend) {
    BvhLayout layout = resolve_bvh_layout(options_.layout, backend);
    if (layout == loaded_.device.bvh_options.layout) return loaded_.device;
    auto found = other_layouts_.find(layout);
    if (found == other_layouts_.end())
        found = other_layouts_.emplace(layout, build_device_scene_for(loaded_.scene, options_, layout)).first;
    return found->second;
}

}  // namespace prism::app
