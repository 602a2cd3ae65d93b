#include "core/loaders/scene_loader.h"

#include <new>

#include "core/loaders/builtin_scenes.h"
#include "core/loaders/environment_maps.h"
#include "core/util/error.h"
#include "core/util/input_file.h"
#include "core/loaders/load_model.h"
#include "core/util/load_progress.h"
#include "core/loaders/load_scene_json.h"
#include "core/util/scene_read_rules.h"
#include "core/scene/seed_material.h"

namespace prism {
namespace {

// A bare model brings geometry and materials only; this gives it a sky, a sun and something to fill shadows.
void add_environment_defaults(Scene& scene, const LoadOptions& options) {
    if (scene.materials.empty()) {
        scene.materials.push_back(default_material());
        for (Mesh& mesh : scene.meshes) mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    }
    std::filesystem::path sky = options.data_dir / "env" / "cubemap-miramar";
    if (is_cube_map_folder(sky)) {
        load_cube_map(sky, scene);
    } else {
        scene.environment = Environment{};
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = {0.6f, 0.7f, 0.85f};
    }
    scene.ambient_light = glm::vec3(0.1f);
}

// Lights come after framing so the point light can sit near the camera.
void add_default_lights(Scene& scene) {
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
    sun.intensity = 0.8f;
    Light lamp;
    lamp.type = LightType::Point;
    glm::vec3 view = scene.camera.target - scene.camera.position;
    float distance = glm::length(view);
    lamp.position = scene.camera.position + scene.camera.up * (0.25f * distance);
    lamp.intensity = 0.5f * distance * distance;  // inverse-square falloff: about 0.5 at the target
    scene.lights.push_back(sun);
    scene.lights.push_back(lamp);
}

}  // namespace

Scene load_scene(const std::string& spec, const LoadOptions& options) {
    LoadProgressScope progress(options.progress);
    Scene scene;
    bool bare_model = false;
    if (!options.animation.empty() && model_format(spec) != ModelFormat::Gltf)
        throw Error(spec + ": --animation picks a glTF file's animation; " +
                    (model_format(spec) == ModelFormat::SceneJson ? "a scene file names one per object (\"animation\")"
                                                                  : "this scene has none"));
    if (spec.rfind(kBuiltinPrefix, 0) == 0) {
        scene = load_builtin_scene(spec.substr(std::string(kBuiltinPrefix).size()), options);
    } else {
        std::filesystem::path path = spec;
        ModelFormat format = model_format(path);
        require_regular_file(path);  // a FIFO or device named .obj must not block or stream for ever
        if (format == ModelFormat::Unknown) throw file_error(spec, "unsupported scene format");
        SceneReadScope rules(path, options.allow_any_path);
        try {
            if (format == ModelFormat::SceneJson) {
                scene = load_scene_json(path);
            } else {
                load_model(path, scene, options.animation);
                add_environment_defaults(scene, options);
                bare_model = true;
            }
        } catch (const std::bad_alloc&) {
            throw file_error(spec, "out of host memory while loading the scene");
        }
    }
    scene.source = spec;
    validate_scene(scene);
    if (!scene.has_camera) frame_scene(scene);
    if (bare_model && scene.lights.empty()) add_default_lights(scene);
    return scene;
}

}  // namespace prism
