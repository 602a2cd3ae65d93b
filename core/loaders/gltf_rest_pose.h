// Prism draws a glTF scene as its nodes place it (the rest pose): animations and skins are never read. tinygltf 2.7
// refuses files that are valid glTF in those parts it does not need — an animation channel whose target names no
// node (KHR_animation_pointer), a skin without inverseBindMatrices (the spec's default: identity matrices) — so
// both are taken out of the JSON before tinygltf parses it (load_gltf.cpp rewrites the JSON once for every edit).
#pragma once

#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace prism {

// Whether a file's JSON text may hold "animations" or "skins" (a cheap look before parsing it).
bool mentions_animation(std::string_view json_text);

struct RestPoseEdit {
    bool changed = false;         // "animations" or "skins" were taken out (nodes keep their "skin" index)
    bool had_animations = false;  // for the warning that they are not played
};

// Takes the top-level "animations" and "skins" out of `document`.
RestPoseEdit remove_animation(nlohmann::json& document);

}  // namespace prism
