#include "core/loaders/environment_maps.h"

#include <array>
#include <vector>

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

// The scene's environment becomes a map of `kind` over these images (sRGB, or RGBE .hdr), added to its textures.
void use_environment_map(Scene& scene, EnvironmentKind kind, const std::vector<std::filesystem::path>& files) {
    Environment environment;
    environment.kind = kind;
    environment.color = glm::vec3(1.0f);
    for (const std::filesystem::path& file : files) {
        scene.textures.push_back(load_texture(file, true));
        environment.textures.push_back(static_cast<uint32_t>(scene.textures.size() - 1));
    }
    scene.environment = environment;
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
    std::vector<std::filesystem::path> faces;
    for (const char* face : kFaceNames) {
        faces.push_back(find_face(folder, face));
        if (faces.back().empty())
            throw file_error((folder / (std::string(face) + ".png")).string(), "cube-map face not found");
    }
    use_environment_map(scene, EnvironmentKind::CubeMap, faces);
}

void load_equirect_map(const std::filesystem::path& file, Scene& scene) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) throw file_error(file.string(), "no such file");
    use_environment_map(scene, EnvironmentKind::Equirect, {file});
}

}  // namespace prism
