#include "core/loaders/environment_maps.h"

#include <array>

#include "core/util/error.h"
#include "core/image/image_io.h"

namespace prism {
namespace {

// scene.h's face order.
constexpr std::array<const char*, 6> kFaceNames = {"right", "left", "up", "down", "front", "back"};
constexpr std::array<const char*, 3> kFaceExtensions = {".png", ".jpg", ".jpeg"};

std::filesystem::path find_face(const std::filesystem::path& folder, const char* face) {
    for (const char* extension : kFaceExtensions) {
        std::filesystem::path found = find_file_case_insensitive(folder, std::string(face) + extension);
        if (!found.empty()) return found;
    }
    return {};
}

}  // namespace

bool is_cube_map_folder(const std::filesystem::path& folder) {
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error)) return false;
    for (const char* face : kFaceNames)
        if (find_face(folder, face).empty()) return false;
    return true;
}

void load_cube_map(const std::filesystem::path& folder, Scene& scene) {
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error)) throw file_error(folder.string(), "no such cube-map folder");
    Environment environment;
    environment.kind = EnvironmentKind::CubeMap;
    environment.color = glm::vec3(1.0f);
    for (const char* face : kFaceNames) {
        std::filesystem::path file = find_face(folder, face);
        if (file.empty()) throw file_error((folder / (std::string(face) + ".png")).string(), "cube-map face not found");
        scene.textures.push_back(load_texture(file, true));
        environment.textures.push_back(static_cast<uint32_t>(scene.textures.size() - 1));
    }
    scene.environment = environment;
}

void load_equirect_map(const std::filesystem::path& file, Scene& scene) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) throw file_error(file.string(), "no such file");
    Environment environment;
    environment.kind = EnvironmentKind::Equirect;
    environment.color = glm::vec3(1.0f);
    scene.textures.push_back(load_texture(file, true));
    environment.textures.push_back(static_cast<uint32_t>(scene.textures.size() - 1));
    scene.environment = environment;
}

}  // namespace prism
