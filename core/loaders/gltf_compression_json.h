// What tinygltf 2.7 refuses in a compressed glTF before Prism can decode it, taken out of the JSON first:
// load_gltf.cpp rewrites the JSON once for every edit.
// - a meshopt "fallback" buffer (extensions.EXT_meshopt_compression.fallback: true) has a byteLength and no data:
//   tinygltf refuses a buffer without a uri in a .gltf and reads one from a .glb's BIN chunk, failing when the
//   fallback's length (the decompressed size) exceeds it. It becomes a 3-byte buffer of its own; the views that
//   use it get decoded data (gltf_meshopt.h).
// - a Draco primitive's index accessor has no bufferView, which tinygltf refuses for indices. The primitive loses
//   its "indices"; the Draco decoder adds an index accessor of its own (gltf_draco.h).
#pragma once

#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace prism {

inline constexpr const char* kMeshoptExtensions[] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};
inline constexpr const char* kDracoExtension = "KHR_draco_mesh_compression";

// Whether a file's JSON text may hold either extension (a cheap look before parsing it).
bool mentions_compression(std::string_view json_text);

// Makes the changes above in `document`; returns whether it changed anything.
bool prepare_for_decompression(nlohmann::json& document);

}  // namespace prism
