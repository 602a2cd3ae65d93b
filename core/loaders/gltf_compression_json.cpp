#include "core/loaders/gltf_compression_json.h"

#include <nlohmann/json.hpp>

namespace prism {
namespace {

// A buffer tinygltf accepts in either container (it refuses an empty data URI): three zero bytes.
constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AAAA";
constexpr int kPlaceholderBytes = 3;

const nlohmann::json* extension(const nlohmann::json& object, const char* name) {
    auto extensions = object.find("extensions");
    if (extensions == object.end() || !extensions->is_object()) return nullptr;
    auto found = extensions->find(name);
    return found != extensions->end() && found->is_object() ? &*found : nullptr;
}

// Whether `object` holds `key` as the boolean true; any other value (a number, a string) is not true. (json::value
// with a bool default would throw on a number, and a file's JSON must never raise more than prism::Error.)
bool is_true(const nlohmann::json& object, const char* key) {
    auto found = object.find(key);
    return found != object.end() && found->is_boolean() && found->get<bool>();
}

bool empty_meshopt_fallbacks(nlohmann::json& document) {
    auto buffers = document.find("buffers");
    if (buffers == document.end() || !buffers->is_array()) return false;
    bool changed = false;
    for (nlohmann::json& buffer : *buffers) {
        if (!buffer.is_object() || buffer.contains("uri")) continue;
        for (const char* name : kMeshoptExtensions) {
            const nlohmann::json* meshopt = extension(buffer, name);
            if (!meshopt || !is_true(*meshopt, "fallback")) continue;
            buffer["uri"] = kPlaceholderUri;
            buffer["byteLength"] = kPlaceholderBytes;
            changed = true;
            break;
        }
    }
    return changed;
}

bool drop_draco_indices(nlohmann::json& document) {
    auto meshes = document.find("meshes");
    if (meshes == document.end() || !meshes->is_array()) return false;
    bool changed = false;
    for (nlohmann::json& mesh : *meshes) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (nlohmann::json& primitive : mesh["primitives"])
            if (primitive.is_object() && extension(primitive, kDracoExtension))
                changed = primitive.erase("indices") > 0 || changed;
    }
    return changed;
}

}  // namespace

bool mentions_compression(std::string_view json_text) {
    return json_text.find("_meshopt_compression\"") != std::string_view::npos ||
           json_text.find(kDracoExtension) != std::string_view::npos;
}

bool prepare_for_decompression(nlohmann::json& document) {
    const bool emptied = empty_meshopt_fallbacks(document);
    const bool dropped = drop_draco_indices(document);
    return emptied || dropped;
}

}  // namespace prism
