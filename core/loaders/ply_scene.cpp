// A PLY file as a scene: its mesh, one instance, and a material per texture its faces use (MeshLab's "comment
// TextureFile"), else the default material.
#include <vector>

#include "core/image/image_io.h"
#include "core/loaders/load_ply.h"
#include "core/loaders/referenced_file.h"
#include "core/scene/seed_material.h"
#include "core/util/error.h"

namespace prism {

void add_ply_model(const std::filesystem::path& path, Scene& scene) {
    const std::string file = path.string();
    PlyDetails details;
    Mesh mesh = load_ply(path, &details);
    scene.warnings.insert(scene.warnings.end(), details.warnings.begin(), details.warnings.end());
    const bool textured = !details.texture_files.empty() && !mesh.uv0.empty();
    if (!details.texture_files.empty() && mesh.uv0.empty())
        scene.warnings.push_back(file + ": names texture '" + details.texture_files[0] +
                                 "' but has no texture coordinates; drawn untextured");

    // The materials of the textures the faces use, in first use; each TextureFile line is loaded once.
    std::vector<uint32_t> material_of(textured ? details.texture_files.size() : 1, UINT32_MAX);
    for (uint32_t& slot : mesh.triangle_materials) {
        const uint32_t texture = textured ? slot : 0u;
        if (material_of[texture] == UINT32_MAX) {
            Material material = default_material();
            if (textured) {
                const std::string& name = details.texture_files[texture];
                const std::filesystem::path texture_path = find_referenced_file(file, name, path.parent_path());
                if (texture_path.empty()) throw file_error(file, "texture '" + name + "' not found");
                scene.textures.push_back(load_texture(texture_path, /*color_data=*/true));
                // The texture is the surface's colour: MeshLab writes its vertex colours (often a flat grey) beside
                // it, and a viewer shows one or the other, never their product.
                material.name = name;
                material.diffuse = glm::vec3(1.0f);
                material.use_vertex_colors = false;
                TextureLayer layer;
                layer.texture = static_cast<uint32_t>(scene.textures.size() - 1);
                layer.mode = TextureMode::Modulate;
                material.textures.push_back(layer);
            }
            material_of[texture] = static_cast<uint32_t>(scene.materials.size());
            scene.materials.push_back(std::move(material));
        }
        slot = material_of[texture];
    }
    if (mesh.name.empty()) mesh.name = path.filename().string();
    scene.meshes.push_back(std::move(mesh));
    Instance instance;
    instance.mesh = static_cast<uint32_t>(scene.meshes.size() - 1);
    instance.name = path.filename().string();
    scene.instances.push_back(std::move(instance));
}

}  // namespace prism
