// Render output formats, chosen by the file's extension: 8-bit sRGB PNG (the display image), 16-bit sRGB PNG
// (--png-depth 16), Radiance .hdr and OpenEXR .exr (the linear radiance, unclamped). Every writer writes a whole
// file or nothing (a temporary sibling renamed into place).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace prism {

enum class ImageFormat { Png8, Png16, Hdr, Exr };

// The format for `path` (.png with `png_depth` 8 or 16, .hdr, .exr; any case). Throws prism::Error naming the file
// or the option for anything else, so a command can check before doing any work.
ImageFormat output_image_format(const std::filesystem::path& path, int png_depth = 8);
// Whether the format is written from the linear radiance (FrameResult::radiance) rather than the 8-bit image.
bool needs_linear_radiance(ImageFormat format);

// rgba: linear float RGBA, row 0 at the top. Writes half-float R, G, B channels, ZIP-compressed; values above 1 are
// kept (half floats reach 65504).
void write_exr(const std::filesystem::path& path, int width, int height, std::span<const float> rgba);
// rgba: linear float RGBA, row 0 at the top. Writes 16-bit RGB PNG, sRGB-encoded (an sRGB chunk says so) with the
// resolve stage's transfer function; like the 8-bit PNG, values clip to [0, 1].
void write_png16(const std::filesystem::path& path, int width, int height, std::span<const float> rgba);

// A rendered frame in `format`: Png8 from `image` (packed RGBA8), the others from `radiance` (linear RGBA).
void write_image(const std::filesystem::path& path, ImageFormat format, int width, int height,
                 std::span<const uint32_t> image, std::span<const float> radiance);

}  // namespace prism
