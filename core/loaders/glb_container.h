// The GLB container (glTF 2.0 binary): a 12-byte header (magic, version, total length), then chunks of (length,
// type, bytes), the JSON chunk first. Only what the loader needs to hand tinygltf a rewritten JSON chunk.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace prism {

struct GlbParts {
    std::string_view header;  // magic and version (8 bytes), as the file has them
    std::string_view json;    // the JSON chunk's bytes
    std::string_view rest;    // every chunk after it, as stored
};

// The parts of `bytes`, or nullopt when they do not start with a JSON chunk that fits (tinygltf then reports).
std::optional<GlbParts> split_glb(std::string_view bytes);

// The first chunk's bytes as far as the file holds them, whatever its type and declared length (for measuring a
// broken file's JSON before tinygltf says what is wrong with it); empty when the file is shorter than the headers.
std::string_view glb_first_chunk(std::string_view bytes);

// The cause when the chunk after the JSON chunk declares more bytes than the file holds after its 8-byte header
// (tinygltf 2.7 checks that length without the header and reads up to 8 bytes past the end); nullopt otherwise.
std::optional<std::string> glb_second_chunk_overrun(std::string_view bytes);

// A GLB of `header`, `json` (padded with blanks to a multiple of 4 bytes) and `rest`; nullopt past 4 GiB.
std::optional<std::string> join_glb(std::string_view header, std::string_view json, std::string_view rest);

}  // namespace prism
