// Turns what the user names with --scene into a Scene: "builtin:sphere|bunny|dragon", a Prism scene file (.json),
// or a bare model (.gltf, .glb, .obj, .ply, .ply.gz), which gets a camera framing it, a default material,
// environment and light. Throws prism::Error ("<file>: <cause>") on anything malformed.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "core/scene/scene.h"

namespace prism {

struct LoadOptions {
    std::filesystem::path data_dir = "../shared/scenes";  // where builtin:bunny/dragon find the Stanford models
    // Let the scene read files outside its own folder (absolute URIs, "../.."); core/util/scene_read_rules.h.
    bool allow_any_path = false;
    // Which animation of a glTF scene plays (load_gltf.h): empty for the first, a number, a name, or "all".
    std::string animation;
    // Called with the fraction of the load done (0 to 1) as the loaders read (core/util/load_progress.h).
    std::function<void(double fraction)> progress;
};

Scene load_scene(const std::string& spec, const LoadOptions& options = {});

// Checks what every backend relies on: indices in range, finite positions/normals/UVs, material and texture
// references valid, at least one triangle (degenerate ones are allowed: build_device_scene leaves them out). Throws
// prism::Error naming the file and element.
void validate_scene(const Scene& scene);

// Places the camera so the whole scene is in view (used for bare models and scenes without a camera).
void frame_scene(Scene& scene);

}  // namespace prism
