#include "core/loaders/load_scene_json.h"

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <map>
#include <optional>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "core/loaders/environment_maps.h"
#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/util/input_file.h"
#include "core/loaders/load_model.h"
#include "core/util/load_progress.h"
#include "core/util/scene_read_rules.h"
#include "core/scene/seed_material.h"

namespace prism {
namespace {

using nlohmann::json;

// Reads one scene file, keeping the key path of every value for messages ("objects[2].transform.scale").
class SceneFileReader {
public:
    SceneFileReader(std::filesystem::path path) : path_(std::move(path)), file_(path_.string()) {
        folder_ = path_.parent_path();
    }

    Scene read() {
        json root = parse();
        expect_keys(root, "", {"camera", "environment", "ambient", "lights", "materials", "objects"});
        Scene scene;
        scene.source = file_;
        if (root.contains("materials")) read_materials(root["materials"], scene);
        if (root.contains("objects")) read_objects(root["objects"], scene);
        if (root.contains("camera")) read_camera(root["camera"], scene);
        if (root.contains("environment")) read_environment(root["environment"], scene);
        if (root.contains("ambient")) scene.ambient_light = vec3(root["ambient"], "ambient");
        if (root.contains("lights")) read_lights(root["lights"], scene);
        return scene;
    }

private:
    json parse() {
        const std::string text = read_input_file(path_);
        try {
            return json::parse(text);
        } catch (const json::exception& error) {  // parse_error, and out_of_range for numbers like 1e999
            throw file_error(file_, "invalid JSON: " + library_message(error.what(), "malformed"));
        }
    }

    [[noreturn]] void fail(const std::string& key_path, const std::string& cause) const {
        throw file_error(file_, (key_path.empty() ? std::string("top level") : key_path) + ": " + cause);
    }

    static std::string join(const std::string& parent, const std::string& key) {
        return parent.empty() ? key : parent + "." + key;
    }
    static std::string element(const std::string& parent, size_t index) {
        return parent + "[" + std::to_string(index) + "]";
    }

    void expect_keys(const json& object, const std::string& key_path,
                     std::initializer_list<const char*> allowed) const {
        if (!object.is_object()) fail(key_path, "expected an object");
        for (const auto& item : object.items()) {
            // Not a structured binding: clang before 16 (the fuzz build's) cannot capture one in a lambda.
            const std::string& key = item.key();
            if (std::none_of(allowed.begin(), allowed.end(), [&](const char* name) { return key == name; }))
                fail(join(key_path, key), "unknown key");
        }
    }

    float number(const json& value, const std::string& key_path) const {
        if (!value.is_number()) fail(key_path, "expected a number");
        return value.get<float>();
    }

    bool boolean(const json& value, const std::string& key_path) const {
        if (!value.is_boolean()) fail(key_path, "expected true or false");
        return value.get<bool>();
    }

    std::string string(const json& value, const std::string& key_path) const {
        if (!value.is_string()) fail(key_path, "expected a string");
        return value.get<std::string>();
    }

    std::vector<float> numbers(const json& value, const std::string& key_path, size_t count) const {
        std::string expected = "expected " + std::to_string(count) + " numbers";
        if (!value.is_array() || value.size() != count) fail(key_path, expected);
        std::vector<float> result;
        for (const json& item : value) {
            if (!item.is_number()) fail(key_path, expected);
            result.push_back(item.get<float>());
        }
        return result;
    }

    glm::vec3 vec3(const json& value, const std::string& key_path) const {
        std::vector<float> v = numbers(value, key_path, 3);
        return {v[0], v[1], v[2]};
    }

    // Colours and IORs may be one number for all three channels.
    glm::vec3 number_or_vec3(const json& value, const std::string& key_path) const {
        if (value.is_number()) return glm::vec3(value.get<float>());
        if (!value.is_array() || value.size() != 3 ||
            std::any_of(value.begin(), value.end(), [](const json& item) { return !item.is_number(); }))
            fail(key_path, "expected a number or 3 numbers");
        return {value[0].get<float>(), value[1].get<float>(), value[2].get<float>()};
    }

    std::filesystem::path relative_file(const json& value, const std::string& key_path, bool must_be_directory) const {
        std::string name = string(value, key_path);
        std::filesystem::path path = folder_ / name;
        std::error_code error;
        // Anything under the exact name counts as found (a FIFO is then refused as such, below).
        bool exists =
            must_be_directory ? std::filesystem::is_directory(path, error) : std::filesystem::exists(path, error);
        if (!exists) {
            std::filesystem::path found = find_file_case_insensitive(folder_, name);
            if (found.empty())
                fail(key_path, "no such " + std::string(must_be_directory ? "folder" : "file") + " '" +
                                   shorten_path(path.string()) + "'");
            path = found;
        }
        check_scene_reference(file_, name, path, key_path);
        if (!must_be_directory) {
            try {
                require_regular_file(path);
            } catch (const Error&) {
                fail(key_path, "'" + shorten(name) + "' is not a regular file (a FIFO, device or directory)");
            }
        }
        return path;
    }

    void read_camera(const json& camera, Scene& scene) const {
        expect_keys(camera, "camera", {"position", "target", "up", "fov"});
        if (camera.contains("position")) scene.camera.position = vec3(camera["position"], "camera.position");
        if (camera.contains("target")) scene.camera.target = vec3(camera["target"], "camera.target");
        if (camera.contains("up")) scene.camera.up = vec3(camera["up"], "camera.up");
        if (camera.contains("fov")) {
            float fov = number(camera["fov"], "camera.fov");
            if (fov <= 0.0f || fov >= 180.0f) fail("camera.fov", "expected degrees between 0 and 180");
            scene.camera.vertical_fov_degrees = fov;
        }
        if (glm::length(scene.camera.target - scene.camera.position) == 0.0f)
            fail("camera", "position and target are the same point");
        scene.has_camera = true;
    }

    void read_environment(const json& environment, Scene& scene) const {
        expect_keys(environment, "environment", {"cubemap", "equirect", "color", "intensity"});
        int kinds = environment.contains("cubemap") + environment.contains("equirect");
        if (kinds > 1) fail("environment", "give one of cubemap or equirect");
        if (environment.contains("cubemap")) {
            load_cube_map(relative_file(environment["cubemap"], "environment.cubemap", true), scene);
        } else if (environment.contains("equirect")) {
            load_equirect_map(relative_file(environment["equirect"], "environment.equirect", false), scene);
        } else {
            scene.environment = Environment{};
            scene.environment.kind = EnvironmentKind::Constant;
        }
        // For a constant environment the colour is the sky; for maps it multiplies the map.
        if (environment.contains("color"))
            scene.environment.color = number_or_vec3(environment["color"], "environment.color");
        if (environment.contains("intensity"))
            scene.environment.intensity = number(environment["intensity"], "environment.intensity");
    }

    void read_lights(const json& lights, Scene& scene) const {
        if (!lights.is_array()) fail("lights", "expected an array");
        for (size_t i = 0; i < lights.size(); ++i) scene.lights.push_back(read_light(lights[i], element("lights", i)));
    }

    // A light's keys, by type: point (position, range), spot (position, direction, range, cone), directional
    // (direction). A key its type does not use is refused, not ignored.
    Light read_light(const json& source, const std::string& key_path) const {
        expect_keys(source, key_path,
                    {"type", "position", "direction", "color", "intensity", "range", "inner_cone_degrees",
                     "outer_cone_degrees"});
        Light light;
        std::string type = source.contains("type") ? string(source["type"], join(key_path, "type")) : "point";
        // Whether the light has key `name`, which its type uses (or refuses) and may require.
        auto key = [&](const std::string& name, bool used, bool required = false) {
            if (required && !source.contains(name)) fail(join(key_path, name), "a " + type + " light needs a " + name);
            if (!used && source.contains(name)) fail(join(key_path, name), "a " + type + " light has no " + name);
            return used && source.contains(name);
        };
        if (type == "point") {
            light.type = LightType::Point;
        } else if (type == "spot") {
            light.type = LightType::Spot;
        } else if (type == "directional") {
            light.type = LightType::Directional;
        } else {
            fail(join(key_path, "type"), "expected \"point\", \"spot\" or \"directional\"");
        }
        const bool placed = light.type != LightType::Directional, aimed = light.type != LightType::Point;
        const bool spot = light.type == LightType::Spot;
        if (key("position", placed, placed)) light.position = vec3(source["position"], join(key_path, "position"));
        if (key("direction", aimed, aimed)) {
            glm::vec3 direction = vec3(source["direction"], join(key_path, "direction"));
            if (glm::length(direction) == 0.0f) fail(join(key_path, "direction"), "must not be zero");
            light.direction = glm::normalize(direction);
        }
        if (key("range", placed)) {
            light.range = number(source["range"], join(key_path, "range"));
            if (!(light.range > 0.0f)) fail(join(key_path, "range"), "must be a distance > 0");
        }
        if (key("inner_cone_degrees", spot))
            light.inner_cone = glm::radians(number(source["inner_cone_degrees"], join(key_path, "inner_cone_degrees")));
        if (key("outer_cone_degrees", spot))
            light.outer_cone = glm::radians(number(source["outer_cone_degrees"], join(key_path, "outer_cone_degrees")));
        if (spot && !(light.inner_cone >= 0.0f && light.inner_cone <= light.outer_cone &&
                      light.outer_cone <= glm::radians(90.0f)))
            fail(key_path, "a spot's cone needs 0 <= inner_cone_degrees <= outer_cone_degrees <= 90");
        if (source.contains("color")) light.color = number_or_vec3(source["color"], join(key_path, "color"));
        if (source.contains("intensity")) light.intensity = number(source["intensity"], join(key_path, "intensity"));
        return light;
    }

    void read_materials(const json& materials, Scene& scene) {
        if (!materials.is_object()) fail("materials", "expected an object of named materials");
        for (const auto& [name, source] : materials.items()) {
            std::string key_path = "materials." + name;
            expect_keys(source, key_path,
                        {"diffuse", "use_vertex_colors", "vertex_colors", "specular", "ambient", "reflectivity",
                         "transmittance", "fresnel", "ior", "thickness", "emissive", "textures"});
            Material material;
            material.name = name;
            auto field = [&](const char* key) { return join(key_path, key); };
            if (source.contains("diffuse")) material.diffuse = number_or_vec3(source["diffuse"], field("diffuse"));
            if (source.contains("use_vertex_colors"))
                material.use_vertex_colors = boolean(source["use_vertex_colors"], field("use_vertex_colors"));
            if (source.contains("vertex_colors")) {
                // How the model's vertex colours combine with `diffuse`: glTF multiplies, the seed replaced.
                std::string rule = string(source["vertex_colors"], field("vertex_colors"));
                if (rule != "multiply" && rule != "replace")
                    fail(field("vertex_colors"), "expected multiply or replace");
                material.vertex_colors_replace = rule == "replace";
            }
            if (source.contains("specular")) material.specular = number_or_vec3(source["specular"], field("specular"));
            if (source.contains("ambient")) material.ambient = number_or_vec3(source["ambient"], field("ambient"));
            if (source.contains("reflectivity"))
                material.reflectivity = unit(source["reflectivity"], field("reflectivity"));
            if (source.contains("transmittance"))
                material.transmittance = unit(source["transmittance"], field("transmittance"));
            if (source.contains("ior")) {
                material.ior = number_or_vec3(source["ior"], field("ior"));
                if (glm::any(glm::lessThan(material.ior, glm::vec3(1.0f)))) fail(field("ior"), "must be at least 1");
            }
            if (source.contains("thickness")) {
                material.thickness = number(source["thickness"], field("thickness"));
                if (material.thickness < 0.0f) fail(field("thickness"), "must not be negative");
            }
            if (source.contains("emissive")) material.emissive = number_or_vec3(source["emissive"], field("emissive"));
            // Without an explicit Fresnel term: Schlick's for anything that transmits, R_f = 1 for the rest.
            if (material.transmittance > 0.0f)
                set_dielectric_fresnel(material, schlick_f0(material.ior.y));
            else
                set_opaque_fresnel(material);
            if (source.contains("fresnel")) {
                const json& fresnel = source["fresnel"];
                expect_keys(fresnel, field("fresnel"), {"bias", "scale", "power"});
                std::string fresnel_path = field("fresnel");
                if (fresnel.contains("bias"))
                    material.fresnel_bias = number(fresnel["bias"], join(fresnel_path, "bias"));
                if (fresnel.contains("scale"))
                    material.fresnel_scale = number(fresnel["scale"], join(fresnel_path, "scale"));
                if (fresnel.contains("power"))
                    material.fresnel_power = number(fresnel["power"], join(fresnel_path, "power"));
            }
            if (source.contains("textures")) read_texture_stack(source["textures"], field("textures"), material, scene);
            scene.materials.push_back(std::move(material));
            material_index_[name] = static_cast<uint32_t>(scene.materials.size() - 1);
        }
    }

    float unit(const json& value, const std::string& key_path) const {
        float v = number(value, key_path);
        if (v < 0.0f || v > 1.0f) fail(key_path, "expected a number in [0, 1]");
        return v;
    }

    void read_texture_stack(const json& textures, const std::string& key_path, Material& material, Scene& scene) {
        if (!textures.is_array()) fail(key_path, "expected an array of texture layers");
        for (size_t i = 0; i < textures.size(); ++i) {
            std::string layer_path = element(key_path, i);
            const json& source = textures[i];
            expect_keys(source, layer_path, {"file", "mode", "env_color", "uv_set"});
            if (!source.contains("file")) fail(join(layer_path, "file"), "missing");
            TextureLayer layer;
            std::filesystem::path file = relative_file(source["file"], join(layer_path, "file"), false);
            auto cached = texture_index_.find(file.string());
            if (cached == texture_index_.end()) {
                scene.textures.push_back(load_texture(file, true));
                cached = texture_index_.emplace(file.string(), static_cast<uint32_t>(scene.textures.size() - 1)).first;
            }
            layer.texture = cached->second;
            if (source.contains("mode")) {
                std::string mode = string(source["mode"], join(layer_path, "mode"));
                static const std::map<std::string, TextureMode> modes = {{"replace", TextureMode::Replace},
                                                                         {"decal", TextureMode::Decal},
                                                                         {"modulate", TextureMode::Modulate},
                                                                         {"blend", TextureMode::Blend}};
                auto found = modes.find(mode);
                if (found == modes.end()) fail(join(layer_path, "mode"), "expected replace, decal, modulate or blend");
                layer.mode = found->second;
            }
            if (source.contains("env_color")) {
                const json& color = source["env_color"];
                if (color.is_array() && color.size() == 4) {
                    std::vector<float> v = numbers(color, join(layer_path, "env_color"), 4);
                    layer.environment_color = {v[0], v[1], v[2], v[3]};
                } else {
                    layer.environment_color = glm::vec4(number_or_vec3(color, join(layer_path, "env_color")), 1.0f);
                }
            }
            if (source.contains("uv_set")) {
                const json& set = source["uv_set"];
                if (!set.is_number_unsigned() || set.get<unsigned>() > 1)
                    fail(join(layer_path, "uv_set"), "expected 0 or 1");
                layer.uv_set = set.get<unsigned>();
            }
            material.textures.push_back(layer);
        }
    }

    glm::mat4 read_transform(const json& transform, const std::string& key_path) const {
        expect_keys(transform, key_path, {"translate", "rotate", "scale"});
        glm::mat4 matrix(1.0f);
        if (transform.contains("translate"))
            matrix = glm::translate(matrix, vec3(transform["translate"], join(key_path, "translate")));
        if (transform.contains("rotate")) {
            const json& rotate = transform["rotate"];
            std::string rotate_path = join(key_path, "rotate");
            expect_keys(rotate, rotate_path, {"axis", "degrees", "quaternion"});
            if (rotate.contains("quaternion")) {
                if (rotate.contains("axis") || rotate.contains("degrees"))
                    fail(rotate_path, "give either quaternion or axis and degrees");
                std::vector<float> q = numbers(rotate["quaternion"], join(rotate_path, "quaternion"), 4);
                glm::quat rotation(q[3], q[0], q[1], q[2]);  // stored x, y, z, w like glTF
                if (glm::length(rotation) == 0.0f) fail(join(rotate_path, "quaternion"), "must not be zero");
                matrix *= glm::mat4_cast(glm::normalize(rotation));
            } else {
                if (!rotate.contains("axis") || !rotate.contains("degrees"))
                    fail(rotate_path,
                         "expected {\"axis\": [x, y, z], \"degrees\": d} or {\"quaternion\": [x, y, z, w]}");
                glm::vec3 axis = vec3(rotate["axis"], join(rotate_path, "axis"));
                if (glm::length(axis) == 0.0f) fail(join(rotate_path, "axis"), "must not be zero");
                float degrees = number(rotate["degrees"], join(rotate_path, "degrees"));
                matrix = glm::rotate(matrix, glm::radians(degrees), glm::normalize(axis));
            }
        }
        if (transform.contains("scale")) {
            glm::vec3 scale = number_or_vec3(transform["scale"], join(key_path, "scale"));
            if (glm::any(glm::equal(scale, glm::vec3(0.0f)))) fail(join(key_path, "scale"), "must not be zero");
            matrix = glm::scale(matrix, scale);
        }
        return matrix;
    }

    InstanceSpin read_spin(const json& spin, const std::string& key_path, const glm::mat4& placement) const {
        expect_keys(spin, key_path, {"axis", "seconds"});
        InstanceSpin result;
        if (spin.contains("axis")) result.axis = vec3(spin["axis"], join(key_path, "axis"));
        if (!(glm::length(result.axis) > 0.0f)) fail(join(key_path, "axis"), "must not be zero");
        result.axis = glm::normalize(result.axis);
        if (!spin.contains("seconds")) fail(join(key_path, "seconds"), "missing");
        result.seconds = number(spin["seconds"], join(key_path, "seconds"));
        if (!(result.seconds > 0.0f)) fail(join(key_path, "seconds"), "must be more than 0");
        result.pivot = glm::vec3(placement[3]);
        return result;
    }

    glm::mat4 read_matrix(const json& value, const std::string& key_path) const {
        std::vector<float> v = numbers(value, key_path, 16);
        glm::mat4 matrix;
        std::copy(v.begin(), v.end(), glm::value_ptr(matrix));  // column-major, as glTF and GLM store it
        if (glm::determinant(glm::mat3(matrix)) == 0.0f) fail(key_path, "matrix is singular");
        return matrix;
    }

    // One model file loaded once; later objects reuse its meshes as instances, a material override included
    // (Instance::material_override: the instances share the mesh).
    struct LoadedModel {
        std::vector<Instance> instances;  // mesh indices already in the scene, transforms in model space
        std::vector<Light> lights;
        NodeAnimation animation;  // a glTF model's animation, its instances numbered as `instances`
    };

    // `animation`: which of a glTF model's animations plays (load_gltf.h); part of the cache key.
    const LoadedModel& load_object_model(const std::filesystem::path& file, const std::string& key_path,
                                         const std::string& animation, Scene& scene) {
        std::string key = file.string();
        key.append("\n").append(animation);
        auto cached = models_.find(key);
        if (cached != models_.end()) return cached->second;
        if (model_format(file) == ModelFormat::SceneJson || model_format(file) == ModelFormat::Unknown)
            fail(join(key_path, "file"), "unsupported model format '" + file.filename().string() +
                                             "' (expected .gltf, .glb, .obj, .ply or .ply.gz)");
        Scene part;
        load_model(file, part, animation);
        for (std::string& warning : part.warnings) scene.warnings.push_back(std::move(warning));

        // Append the part's textures, materials and meshes, shifting every index by what is already there.
        auto texture_offset = static_cast<uint32_t>(scene.textures.size());
        auto material_offset = static_cast<uint32_t>(scene.materials.size());
        auto mesh_offset = static_cast<uint32_t>(scene.meshes.size());
        for (Texture& texture : part.textures) scene.textures.push_back(std::move(texture));
        for (Material& material : part.materials) {
            for (TextureLayer& layer : material.textures) layer.texture += texture_offset;
            scene.materials.push_back(std::move(material));
        }
        for (Mesh& mesh : part.meshes) {
            for (uint32_t& material : mesh.triangle_materials) material += material_offset;
            scene.meshes.push_back(std::move(mesh));
        }
        LoadedModel model;
        for (Instance& instance : part.instances) {
            instance.mesh += mesh_offset;
            model.instances.push_back(std::move(instance));
        }
        model.lights = part.lights;
        model.animation = std::move(part.animation);
        for (MeshDeformation& deformation : model.animation.deformations) deformation.mesh += mesh_offset;
        return models_.emplace(key, std::move(model)).first->second;
    }

    // An object's "animation": a glTF model's animation by index or name, or "all" (docs/scene-format.md).
    std::string read_animation_choice(const json& source, const std::string& key_path,
                                      const std::filesystem::path& file) const {
        if (!source.contains("animation")) return {};
        const std::string path = join(key_path, "animation");
        const json& value = source["animation"];
        std::string choice;
        if (value.is_number_unsigned())
            choice = std::to_string(value.get<uint64_t>());
        else if (value.is_string() && !value.get<std::string>().empty())
            choice = value.get<std::string>();
        else
            fail(path, "expected an animation's index (0, 1, ...), its name, or \"all\"");
        if (model_format(file) != ModelFormat::Gltf) fail(path, "only glTF models have animations");
        return choice;
    }

    void read_objects(const json& objects, Scene& scene) {
        if (!objects.is_array()) fail("objects", "expected an array");
        for (size_t i = 0; i < objects.size(); ++i) {
            LoadProgressShare share(double(i) / double(objects.size()), double(i + 1) / double(objects.size()));
            std::string key_path = element("objects", i);
            const json& source = objects[i];
            expect_keys(source, key_path, {"file", "transform", "matrix", "material", "name", "spin", "animation"});
            if (!source.contains("file")) fail(join(key_path, "file"), "missing");
            if (source.contains("transform") && source.contains("matrix"))
                fail(key_path, "give either transform or matrix");
            glm::mat4 placement(1.0f);
            if (source.contains("transform"))
                placement = read_transform(source["transform"], join(key_path, "transform"));
            if (source.contains("matrix")) placement = read_matrix(source["matrix"], join(key_path, "matrix"));
            std::string material;
            if (source.contains("material")) {
                material = string(source["material"], join(key_path, "material"));
                if (!material_index_.count(material))
                    fail(join(key_path, "material"), "no material named '" + material + "' in materials");
            }
            std::string name = source.contains("name") ? string(source["name"], join(key_path, "name")) : "";
            std::filesystem::path file = relative_file(source["file"], join(key_path, "file"), false);
            const std::string animation = read_animation_choice(source, key_path, file);
            const LoadedModel& model = load_object_model(file, key_path, animation, scene);
            std::optional<InstanceSpin> spin;
            if (source.contains("spin")) spin = read_spin(source["spin"], join(key_path, "spin"), placement);
            append_node_animation(scene.animation, model.animation, static_cast<uint32_t>(scene.instances.size()),
                                  static_cast<uint32_t>(scene.lights.size()), placement);
            for (const Instance& part : model.instances) {
                Instance instance = part;
                instance.transform = placement * part.transform;
                if (!material.empty()) instance.material_override = material_index_.at(material);
                if (!name.empty()) instance.name = name;
                if (spin) {
                    spin->instance = static_cast<uint32_t>(scene.instances.size());
                    scene.spins.push_back(*spin);
                }
                scene.instances.push_back(std::move(instance));
            }
            for (Light light : model.lights) {
                light.position = glm::vec3(placement * glm::vec4(light.position, 1.0f));
                light.direction = glm::normalize(glm::vec3(placement * glm::vec4(light.direction, 0.0f)));
                scene.lights.push_back(light);
            }
        }
    }

    std::filesystem::path path_;
    std::string file_;
    std::filesystem::path folder_;
    std::map<std::string, uint32_t> material_index_;
    std::map<std::string, uint32_t> texture_index_;
    std::map<std::string, LoadedModel> models_;  // by file
};

}  // namespace

Scene load_scene_json(const std::filesystem::path& path) { return SceneFileReader(path).read(); }

}  // namespace prism
