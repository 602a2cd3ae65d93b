// The per-format checks behind core/image/image_guard.h, one file per format family. Each throws prism::Error
// "<name>: corrupt|truncated <FORMAT> (<cause>)" for what Debian's stb_image (2.27) would mishandle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace prism::image_guard {

// stb_image takes a file for a JPEG when it starts with 0xff, any number of 0xff fill bytes, then SOI (0xd8):
// the index of that 0xd8, or 0 when the file is no JPEG to stb.
size_t jpeg_start_of_image(std::span<const uint8_t> bytes);

// Structure, before stb reads anything (image_guard_jpeg.cpp, image_guard_png.cpp).
void check_jpeg(std::span<const uint8_t> bytes, const std::string& name);
void check_png(std::span<const uint8_t> bytes, const std::string& name);

// Whether the file can hold the width x height pixels its header declares (image_guard_raster.cpp: stb reads
// these formats byte by byte and zero-fills past the end of the file, or, for HDR, loops for ever).
void check_jpeg_size(std::span<const uint8_t> bytes, const std::string& name, int width, int height);
void check_tga(std::span<const uint8_t> bytes, const std::string& name, int width, int height);
void check_bmp(std::span<const uint8_t> bytes, const std::string& name, int width, int height);
void check_hdr(std::span<const uint8_t> bytes, const std::string& name, int width, int height);

}  // namespace prism::image_guard
