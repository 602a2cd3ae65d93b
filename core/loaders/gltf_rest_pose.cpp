#include "core/loaders/gltf_rest_pose.h"

#include <nlohmann/json.hpp>

#include "core/loaders/glb_container.h"

namespace prism {

std::optional<RestPoseGltf> gltf_without_animation(std::string_view bytes, bool binary) {
    std::optional<GlbParts> glb;
    if (binary && !(glb = split_glb(bytes))) return std::nullopt;  // tinygltf reports a broken container
    const std::string_view json_text = binary ? glb->json : bytes;
    // A cheap look first: most files have neither, and parsing a large .gltf's embedded buffers twice is not free.
    if (json_text.find("\"animations\"") == std::string_view::npos &&
        json_text.find("\"skins\"") == std::string_view::npos)
        return std::nullopt;
    nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
    if (document.is_discarded() || !document.is_object()) return std::nullopt;
    const bool had_animations = document.erase("animations") > 0;
    const bool had_skins = document.erase("skins") > 0;
    if (!had_animations && !had_skins) return std::nullopt;

    std::string json = document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (!binary) return RestPoseGltf{std::move(json), had_animations};
    std::optional<std::string> repacked = join_glb(glb->header, json, glb->rest);
    if (!repacked) return std::nullopt;
    return RestPoseGltf{std::move(*repacked), had_animations};
}

}  // namespace prism
