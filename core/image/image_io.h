// Image files: textures in (PNG, JPEG, TGA, BMP through stb_image, WebP through libwebp; Radiance .hdr kept as RGBE
// texels), renders out (8-bit sRGB PNG; linear float .hdr). Outputs are written to a temporary name and renamed,
// so a failed write never leaves a partial file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "core/scene/scene.h"

namespace prism {

// Loads a texture. `color_data` chooses sRGB (base colour, emissive) or linear (data) decoding of 8-bit images;
// .hdr files always load as RGBE. Throws prism::Error "<file>: <cause>".
Texture load_texture(const std::filesystem::path& path, bool color_data = true);
// The same from bytes in memory (embedded glTF images); `name` is used in messages.
Texture load_texture_from_memory(std::span<const uint8_t> bytes, const std::string& name, bool color_data = true);

// Finds `relative` under `directory`, matching each path component case-insensitively when the exact name is
// missing (real OBJ/MTL files name "KAMEN.JPG" as "kamen.jpg"). Returns an empty path when nothing matches.
std::filesystem::path find_file_case_insensitive(const std::filesystem::path& directory, const std::string& relative);

// rgba8: packed RGBA8 (r in the low byte), row 0 at the top.
void write_png(const std::filesystem::path& path, int width, int height, std::span<const uint32_t> rgba8);
// rgba: linear float RGBA, row 0 at the top. Writes Radiance .hdr (RGBE).
void write_hdr(const std::filesystem::path& path, int width, int height, std::span<const float> rgba);
// Either of the above by extension (.png, .hdr); anything else throws before any work is done.
void check_output_extension(const std::filesystem::path& path);

}  // namespace prism
