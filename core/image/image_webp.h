// WebP textures through libwebp: the images of glTF's EXT_texture_webp (what gltf-transform's `optimize` writes by
// default), and any texture file in WebP. stb_image does not read WebP.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace prism {

// "RIFF", a length, "WEBP": the container every WebP file starts with.
bool is_webp(std::span<const uint8_t> bytes);

struct Rgba8Pixels {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;  // width * height * 4, row 0 at the top
};

// Decodes a still WebP image (lossy or lossless, with or without alpha) after checking its header against the
// texture limits (image_guard.h) and the scene's texture budget. Throws prism::Error "<name>: <cause>" for a
// header libwebp cannot read, an animated image, a size over the limits or data that do not decode.
Rgba8Pixels decode_webp(std::span<const uint8_t> bytes, const std::string& name);

}  // namespace prism
