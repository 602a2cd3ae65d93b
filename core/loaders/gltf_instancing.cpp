#include "core/loaders/gltf_instancing.h"

#include <algorithm>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <tiny_gltf.h>

#include "core/util/error.h"
#include "core/loaders/gltf_accessor.h"

namespace prism::gltf {

std::vector<glm::mat4> gpu_instance_transforms(const tinygltf::Model& model, const tinygltf::Node& node,
                                               const std::string& file) {
    auto found = node.extensions.find("EXT_mesh_gpu_instancing");
    if (found == node.extensions.end() || !found->second.Has("attributes")) return {glm::mat4(1.0f)};
    const tinygltf::Value& attributes = found->second.Get("attributes");
    const std::string what = "node '" + node.name + "': EXT_mesh_gpu_instancing";

    auto read = [&](const char* name, int components) {
        FloatArray array;
        if (!attributes.Has(name) || !attributes.Get(name).IsNumber()) return array;
        array = read_floats(model, attributes.Get(name).GetNumberAsInt(), file);
        if (array.components != components)
            throw file_error(file, what + ": " + name + " must have " + std::to_string(components) + " components");
        return array;
    };
    FloatArray translation = read("TRANSLATION", 3);
    FloatArray rotation = read("ROTATION", 4);
    FloatArray scale = read("SCALE", 3);
    size_t count = std::max({translation.count, rotation.count, scale.count});
    for (const FloatArray* array : {&translation, &rotation, &scale})
        if (array->count != 0 && array->count != count)
            throw file_error(file, what + ": attribute counts differ (" + std::to_string(array->count) + " and " +
                                       std::to_string(count) + ")");
    if (count == 0) return {glm::mat4(1.0f)};

    std::vector<glm::mat4> transforms(count, glm::mat4(1.0f));
    for (size_t i = 0; i < count; ++i) {
        glm::mat4& m = transforms[i];
        if (translation.count)
            m = glm::translate(m, {translation.at(i, 0), translation.at(i, 1), translation.at(i, 2)});
        if (rotation.count) {
            glm::quat q(rotation.at(i, 3), rotation.at(i, 0), rotation.at(i, 1), rotation.at(i, 2));  // w, x, y, z
            if (glm::dot(q, q) > 0.0f) m *= glm::mat4_cast(glm::normalize(q));
        }
        if (scale.count) m = glm::scale(m, {scale.at(i, 0), scale.at(i, 1), scale.at(i, 2)});
    }
    return transforms;
}

}  // namespace prism::gltf
