#include "core/image/image_output.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "core/util/error.h"
#include "core/image/image_io.h"

namespace prism {

ImageFormat output_image_format(const std::filesystem::path& path, int png_depth) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (png_depth != 8 && png_depth != 16)
        throw Error("--png-depth: " + std::to_string(png_depth) + " is not a PNG depth Prism writes (use 8 or 16)");
    if (extension == ".png") return png_depth == 16 ? ImageFormat::Png16 : ImageFormat::Png8;
    if (png_depth != 8)
        throw Error(path.string() + ": --png-depth applies to .png output only, not '" + path.extension().string() +
                    "'");
    if (extension == ".hdr") return ImageFormat::Hdr;
    if (extension == ".exr") return ImageFormat::Exr;
    throw file_error(path.string(),
                     "unsupported output format '" + path.extension().string() + "' (use .png, .exr or .hdr)");
}

bool needs_linear_radiance(ImageFormat format) { return format != ImageFormat::Png8; }

void write_image(const std::filesystem::path& path, ImageFormat format, int width, int height,
                 std::span<const uint32_t> image, std::span<const float> radiance) {
    switch (format) {
        case ImageFormat::Png8: return write_png(path, width, height, image);
        case ImageFormat::Png16: return write_png16(path, width, height, radiance);
        case ImageFormat::Hdr: return write_hdr(path, width, height, radiance);
        case ImageFormat::Exr: return write_exr(path, width, height, radiance);
    }
}

}  // namespace prism
