#include "core/util/scene_read_rules.h"

#include <system_error>

#include "core/util/error.h"

namespace prism {
namespace {

struct Rules {
    bool active = false;
    std::filesystem::path root;  // canonical folder of the scene file
    bool allow_any_path = false;
    uint64_t texture_bytes = 0;
};

// Loading is single-threaded per scene; thread_local keeps two scenes loading on two threads apart.
thread_local Rules current;

std::filesystem::path canonical_folder_of(const std::filesystem::path& file) {
    std::error_code error;
    std::filesystem::path absolute = std::filesystem::absolute(file, error);
    std::filesystem::path folder = std::filesystem::weakly_canonical(absolute.parent_path(), error);
    return error ? absolute.parent_path().lexically_normal() : folder;
}

bool lies_within(const std::filesystem::path& path, const std::filesystem::path& folder) {
    auto p = path.begin();
    for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
        if (f->empty()) continue;  // a trailing separator
        if (p == path.end() || *p != *f) return false;
    }
    return true;
}

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

}  // namespace

struct SceneReadScope::Saved {
    Rules rules;
};

SceneReadScope::SceneReadScope(const std::filesystem::path& scene_file, bool allow_any_path)
    : saved_(new Saved{current}) {
    current = Rules{true, canonical_folder_of(scene_file), allow_any_path, 0};
}

SceneReadScope::~SceneReadScope() {
    current = saved_->rules;
    delete saved_;
}

void check_scene_reference(const std::string& referring_file, const std::string& reference,
                           const std::filesystem::path& resolved, const std::string& where) {
    if (current.active && current.allow_any_path) return;
    const std::filesystem::path root = current.active ? current.root : canonical_folder_of(referring_file);
    std::error_code error;
    // Symbolic links are followed: a link inside the folder pointing elsewhere does not lie in the folder.
    std::filesystem::path target = std::filesystem::weakly_canonical(std::filesystem::absolute(resolved, error), error);
    if (error) target = std::filesystem::absolute(resolved).lexically_normal();
    const bool absolute = !reference.empty() && (reference.front() == '/' || reference.front() == '\\');
    if (lies_within(target, root)) return;
    throw file_error(referring_file, (where.empty() ? "" : where + ": ") + "'" + shorten(reference) + "' " +
                                         (absolute ? "is an absolute path" : "lies outside the scene's folder") +
                                         "; a scene reads only files in or below its own folder (" + root.string() +
                                         ") unless --allow-any-path is given");
}

void charge_texture_bytes(const std::string& name, uint64_t bytes) {
    const uint64_t used = current.active ? current.texture_bytes : 0;
    if (bytes > kSceneTextureBudgetBytes - used)
        throw file_error(name, "texture needs " + mib(bytes) + " with " + mib(used) +
                                   " already used by the scene's textures; a scene's textures may take " +
                                   mib(kSceneTextureBudgetBytes));
    if (current.active) current.texture_bytes += bytes;
}

}  // namespace prism
