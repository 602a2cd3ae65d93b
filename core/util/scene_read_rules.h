// What a scene may make Prism read while it loads: files in or below the scene's own folder (unless the user
// passed --allow-any-path), and textures up to a per-scene budget. A scene is data from elsewhere; without these
// a glTF URI "../../../../etc/passwd" is read, and eight textures each allowed alone take gigabytes together.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/util/non_copyable.h"

namespace prism {

// Texel memory one scene may decode (every texture, environment maps included).
constexpr uint64_t kSceneTextureBudgetBytes = uint64_t(512) << 20;

// The rules while one scene loads (load_scene opens one around its loaders). Without an open scope, a loader
// called on its own applies them to its own file's folder, and the texture budget counts per texture.
class SceneReadScope : private NonCopyable {
public:
    SceneReadScope(const std::filesystem::path& scene_file, bool allow_any_path);
    ~SceneReadScope();

private:
    struct Saved;
    Saved* saved_;
};

// Checks a file that `referring_file` names as `reference` (the URI or path as written) and that resolved to
// `resolved`: it must lie in or below the scene's folder, unless any path is allowed. Throws prism::Error
// "<referring_file>: [<where>: ]'<reference>' <rule>" (`where`: a key path in a scene file).
void check_scene_reference(const std::string& referring_file, const std::string& reference,
                           const std::filesystem::path& resolved, const std::string& where = {});

// Counts `bytes` of texels for the texture `name` against the scene's budget; throws prism::Error naming the
// texture when the scene's textures would exceed it. Called before the texture is decoded.
void charge_texture_bytes(const std::string& name, uint64_t bytes);

}  // namespace prism
