// Prism draws a still glTF scene as its nodes place it, and skins are applied in that pose (gltf_skin.h); sequences
// and the viewer play the first animation's node transforms (gltf_animation.h). tinygltf 2.7 refuses files that are
// valid glTF in those parts — an animation channel whose target names no node (KHR_animation_pointer), a skin without
// inverseBindMatrices (the spec's default: identity matrices) — so both are taken out of the JSON before tinygltf
// parses it (load_gltf.cpp rewrites the JSON once for every edit), and handed to the importer as JSON.
#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

namespace prism {

// Whether a file's JSON text may hold "animations" or "skins" (a cheap look before parsing it).
bool mentions_animation(std::string_view json_text);

struct RestPoseEdit {
    bool changed = false;       // "animations" or "skins" were taken out (nodes keep their "skin" index)
    nlohmann::json animations;  // the "animations" array taken out (null when there was none)
    nlohmann::json skins;       // the "skins" array taken out (null when there was none)
};

// Takes the top-level "animations" and "skins" out of `document`; both come back in the edit.
RestPoseEdit remove_animation(nlohmann::json& document);

}  // namespace prism
