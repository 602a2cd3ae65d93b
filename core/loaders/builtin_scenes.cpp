#include "core/loaders/builtin_scenes.h"

#include <algorithm>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "core/loaders/environment_maps.h"
#include "core/util/error.h"
#include "core/loaders/load_ply.h"
#include "core/scene/procedural.h"
#include "core/scene/seed_material.h"

namespace prism {
namespace {

// Everything shared by the three scenes is sized for a model about two units tall standing at the origin.
constexpr float kPlaneSize = 12.0f;

uint32_t add_material(Scene& scene, Material material) {
    scene.materials.push_back(std::move(material));
    return static_cast<uint32_t>(scene.materials.size() - 1);
}

uint32_t add_mesh(Scene& scene, Mesh mesh, uint32_t material) {
    mesh.triangle_materials.assign(mesh.triangles.size(), material);
    scene.meshes.push_back(std::move(mesh));
    return static_cast<uint32_t>(scene.meshes.size() - 1);
}

void add_instance(Scene& scene, uint32_t mesh, const glm::mat4& transform, const std::string& name) {
    Instance instance;
    instance.mesh = mesh;
    instance.transform = transform;
    instance.name = name;
    scene.instances.push_back(std::move(instance));
}

Material glass(const std::string& name, glm::vec3 ior) {
    Material material;
    material.name = name;
    material.diffuse = glm::vec3(1.0f);
    material.reflectivity = 0.3f;
    material.transmittance = 0.9f;
    material.ior = ior;
    set_dielectric_fresnel(material, schlick_f0(ior.y));
    return material;
}

Material mirror(const std::string& name, glm::vec3 diffuse, float reflectivity) {
    Material material;
    material.name = name;
    material.diffuse = diffuse;
    material.use_vertex_colors = false;
    material.specular = glm::vec3(0.95f);
    material.reflectivity = reflectivity;
    set_opaque_fresnel(material);
    return material;
}

// The textured, slightly reflective floor every seed scene stands on.
void add_checker_floor(Scene& scene) {
    scene.textures.push_back(make_checker_texture(512, 16, glm::vec3(0.9f), glm::vec3(0.15f)));
    Material floor;
    floor.name = "checker floor";
    floor.diffuse = glm::vec3(1.0f);
    floor.use_vertex_colors = false;
    floor.reflectivity = 0.25f;
    set_opaque_fresnel(floor);
    TextureLayer layer;
    layer.texture = static_cast<uint32_t>(scene.textures.size() - 1);
    layer.mode = TextureMode::Modulate;
    floor.textures.push_back(layer);
    uint32_t material = add_material(scene, floor);
    add_instance(scene, add_mesh(scene, make_ground_plane(kPlaneSize), material), glm::mat4(1.0f), "floor");
}

void add_procedural_sky(Scene& scene) {
    Environment environment;
    environment.kind = EnvironmentKind::CubeMap;
    environment.color = glm::vec3(1.0f);
    for (Texture& face : make_sky_cube_map(64)) {
        scene.textures.push_back(std::move(face));
        environment.textures.push_back(static_cast<uint32_t>(scene.textures.size() - 1));
    }
    scene.environment = environment;
}

void add_lights(Scene& scene) {
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
    sun.color = {1.0f, 0.96f, 0.9f};
    sun.intensity = 0.8f;
    Light lamp;
    lamp.type = LightType::Point;
    lamp.position = {3.0f, 5.0f, 4.0f};
    lamp.intensity = 25.0f;  // inverse-square: about 0.5 at the model, 7 units away
    scene.lights = {sun, lamp};
    scene.ambient_light = glm::vec3(0.1f);
}

void set_camera(Scene& scene, glm::vec3 position, glm::vec3 target) {
    scene.camera.position = position;
    scene.camera.target = target;
    scene.camera.up = {0.0f, 1.0f, 0.0f};
    scene.camera.vertical_fov_degrees = 45.0f;
    scene.has_camera = true;
}

// Stands a model on the floor: scaled so its largest extent is `size`, centred on `centre` (x, z), touching y = 0.
glm::mat4 stand_on_floor(const Mesh& mesh, float size, glm::vec2 centre) {
    glm::vec3 low(std::numeric_limits<float>::max()), high(std::numeric_limits<float>::lowest());
    for (const glm::vec3& p : mesh.positions) {
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    glm::vec3 extent = high - low;
    float scale = size / std::max({extent.x, extent.y, extent.z, 1e-20f});
    glm::vec3 anchor{(low.x + high.x) * 0.5f, low.y, (low.z + high.z) * 0.5f};
    return glm::translate(glm::mat4(1.0f), glm::vec3(centre.x, 0.0f, centre.y)) *
           glm::scale(glm::mat4(1.0f), glm::vec3(scale)) * glm::translate(glm::mat4(1.0f), -anchor);
}

Mesh load_data_model(const LoadOptions& options, const std::string& relative, const std::string& scene_name) {
    std::filesystem::path path = options.data_dir / relative;
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
        throw file_error(path.string(), "no such file (builtin:" + scene_name +
                                            " needs the Stanford models; point --data-dir at the scenes folder)");
    return load_ply(path);
}

void add_data_environment(Scene& scene, const LoadOptions& options) {
    std::filesystem::path folder = options.data_dir / "env" / "cubemap-miramar";
    if (is_cube_map_folder(folder)) {
        load_cube_map(folder, scene);
    } else {
        scene.warnings.push_back(folder.string() + ": cube map not found; using the procedural sky");
        add_procedural_sky(scene);
    }
}

Scene sphere_scene() {
    Scene scene;
    add_checker_floor(scene);
    // ~10,000 triangles like the seed's sphere; the gradient in its vertex colours tints the glass.
    uint32_t glass_material = add_material(scene, glass("dispersive glass", {1.50f, 1.52f, 1.54f}));
    add_instance(scene, add_mesh(scene, make_uv_sphere(50, 100), glass_material),
                 glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)), "glass sphere");
    add_procedural_sky(scene);
    add_lights(scene);
    set_camera(scene, {0.0f, 2.2f, 5.5f}, {0.0f, 0.8f, 0.0f});
    return scene;
}

// A Stanford model standing on the checker floor with a small sphere beside it, under the cube map and the lights.
struct ModelScene {
    const char* file;  // under --data-dir
    const char* name;  // the builtin scene's and the model's instance
    float size;        // the model's largest extent
    Material material;
    Material sphere_material;
    const char* sphere_name;
    glm::vec3 sphere_centre;  // radius 0.5, so y = 0.5 rests it on the floor
    glm::vec3 camera_position;
    glm::vec3 camera_target;
};

Scene model_scene(const LoadOptions& options, const ModelScene& spec) {
    Scene scene;
    Mesh model = load_data_model(options, spec.file, spec.name);
    glm::mat4 placement = stand_on_floor(model, spec.size, {0.0f, 0.0f});
    add_checker_floor(scene);
    uint32_t material = add_material(scene, spec.material);
    add_instance(scene, add_mesh(scene, std::move(model), material), placement, spec.name);
    uint32_t sphere_material = add_material(scene, spec.sphere_material);
    add_instance(scene, add_mesh(scene, make_uv_sphere(24, 48), sphere_material),
                 glm::translate(glm::mat4(1.0f), spec.sphere_centre) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f)),
                 spec.sphere_name);
    add_data_environment(scene, options);
    add_lights(scene);
    set_camera(scene, spec.camera_position, spec.camera_target);
    return scene;
}

Scene bunny_scene(const LoadOptions& options) {
    Material small_glass = glass("glass", glm::vec3(1.5f));
    small_glass.use_vertex_colors = false;
    return model_scene(options, {.file = "stanford/bunny.ply",
                                 .name = "bunny",
                                 .size = 2.0f,
                                 .material = mirror("bunny mirror", glm::vec3(0.75f, 0.75f, 0.8f), 0.6f),
                                 .sphere_material = small_glass,
                                 .sphere_name = "glass sphere",
                                 .sphere_centre = {1.8f, 0.5f, 0.8f},
                                 .camera_position = {0.0f, 2.0f, 5.5f},
                                 .camera_target = {0.3f, 0.9f, 0.0f}});
}

Scene dragon_scene(const LoadOptions& options) {
    Material dragon_glass = glass("dispersive glass", {1.50f, 1.53f, 1.56f});
    dragon_glass.diffuse = {0.85f, 0.95f, 0.9f};
    dragon_glass.use_vertex_colors = false;
    return model_scene(options, {.file = "stanford/dragon.ply.gz",
                                 .name = "dragon",
                                 .size = 3.0f,
                                 .material = dragon_glass,
                                 .sphere_material = mirror("mirror", glm::vec3(0.8f), 0.8f),
                                 .sphere_name = "mirror sphere",
                                 .sphere_centre = {2.0f, 0.5f, 1.0f},
                                 .camera_position = {0.0f, 2.3f, 6.0f},
                                 .camera_target = {0.3f, 0.9f, 0.0f}});
}

}  // namespace

std::vector<std::string> builtin_scene_names() { return {"sphere", "bunny", "dragon"}; }

Scene load_builtin_scene(const std::string& name, const LoadOptions& options) {
    Scene scene;
    if (name == "sphere")
        scene = sphere_scene();
    else if (name == "bunny")
        scene = bunny_scene(options);
    else if (name == "dragon")
        scene = dragon_scene(options);
    else
        throw file_error(kBuiltinPrefix + name, "unknown built-in scene (known: sphere, bunny, dragon)");
    scene.source = kBuiltinPrefix + name;
    return scene;
}

}  // namespace prism
