#include "core/loaders/load_model.h"

#include <algorithm>

#include "core/util/error.h"
#include "core/loaders/load_gltf.h"
#include "core/loaders/load_obj.h"
#include "core/loaders/load_ply.h"

namespace prism {
namespace {

bool ends_with(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

ModelFormat model_format(const std::filesystem::path& path) {
    std::string name = path.filename().string();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ends_with(name, ".gltf") || ends_with(name, ".glb")) return ModelFormat::Gltf;
    if (ends_with(name, ".obj")) return ModelFormat::Obj;
    if (ends_with(name, ".ply") || ends_with(name, ".ply.gz")) return ModelFormat::Ply;
    if (ends_with(name, ".json")) return ModelFormat::SceneJson;
    return ModelFormat::Unknown;
}

void load_model(const std::filesystem::path& path, Scene& scene, const std::string& animation) {
    const ModelFormat format = model_format(path);
    if (!animation.empty() && format != ModelFormat::Gltf)
        throw file_error(path.string(), "has no animations to play (--animation picks a glTF file's)");
    switch (format) {
        case ModelFormat::Gltf: load_gltf(path, scene, animation); return;
        case ModelFormat::Obj: load_obj(path, scene); return;
        case ModelFormat::Ply: add_ply_model(path, scene); return;
        default: throw file_error(path.string(), "unsupported scene format");
    }
}

}  // namespace prism
