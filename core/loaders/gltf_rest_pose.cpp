#include "core/loaders/gltf_rest_pose.h"

#include <nlohmann/json.hpp>

namespace prism {

bool mentions_animation(std::string_view json_text) {
    return json_text.find("\"animations\"") != std::string_view::npos ||
           json_text.find("\"skins\"") != std::string_view::npos;
}

RestPoseEdit remove_animation(nlohmann::json& document) {
    RestPoseEdit edit;
    bool had_animations = false;
    if (auto animations = document.find("animations"); animations != document.end()) {
        edit.animations = std::move(*animations);
        document.erase(animations);
        had_animations = true;
    }
    bool had_skins = false;
    if (auto skins = document.find("skins"); skins != document.end()) {
        edit.skins = std::move(*skins);
        document.erase(skins);
        had_skins = true;
    }
    edit.changed = had_animations || had_skins;
    return edit;
}

}  // namespace prism
