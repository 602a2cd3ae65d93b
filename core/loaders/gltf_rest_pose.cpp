#include "core/loaders/gltf_rest_pose.h"

#include <nlohmann/json.hpp>

namespace prism {

bool mentions_animation(std::string_view json_text) {
    return json_text.find("\"animations\"") != std::string_view::npos ||
           json_text.find("\"skins\"") != std::string_view::npos;
}

RestPoseEdit remove_animation(nlohmann::json& document) {
    RestPoseEdit edit;
    edit.had_animations = document.erase("animations") > 0;
    const bool had_skins = document.erase("skins") > 0;
    edit.changed = edit.had_animations || had_skins;
    return edit;
}

}  // namespace prism
