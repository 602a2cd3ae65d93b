// Prism draws a glTF scene as its nodes place it (the rest pose): animations and skins are never read. tinygltf 2.7
// refuses files that are valid glTF in those parts it does not need — an animation channel whose target names no
// node (KHR_animation_pointer), a skin without inverseBindMatrices (the spec's default: identity matrices) — so
// both are taken out of the JSON before tinygltf parses it.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace prism {

struct RestPoseGltf {
    std::string bytes;    // the .gltf text or the .glb container, without "animations" and "skins"
    bool had_animations;  // for the warning that they are not played
};

// `bytes` (a .gltf, or a .glb when `binary`) without its top-level "animations" and "skins" (nodes keep their
// "skin" index); nullopt when it has neither, or when its JSON does not parse (tinygltf then reports the error).
std::optional<RestPoseGltf> gltf_without_animation(std::string_view bytes, bool binary);

}  // namespace prism
