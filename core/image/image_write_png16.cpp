// 16-bit PNG output through libpng (stb_image_write writes 8-bit PNG only). The encoding is the one the resolve
// stage uses for the 8-bit image (kernels/texture.h), with 257 times the steps.
#include <csetjmp>
#include <string>
#include <vector>

#include <png.h>

#include "core/util/error.h"
#include "core/image/image_output.h"
#include "core/util/output_file.h"
#include "kernels/texture.h"

namespace prism {
namespace {

void append_to_string(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::string*>(png_get_io_ptr(png));
    try {
        out->append(reinterpret_cast<const char*>(data), length);
    } catch (...) {
        png_error(png, "out of host memory");
    }
}

void remember_error(png_structp png, png_const_charp message) {
    auto* cause = static_cast<std::string*>(png_get_error_ptr(png));
    if (cause->empty()) *cause = message;
    png_longjmp(png, 1);
}

// Only plain data lives in this frame: libpng leaves it by longjmp on an error.
bool encode_png16(const png_bytep* rows, int width, int height, std::string* out, std::string* cause) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, cause, remember_error, nullptr);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, info ? &info : nullptr);
        return false;
    }
    png_set_write_fn(png, out, append_to_string, nullptr);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 16, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    png_write_image(png, const_cast<png_bytepp>(rows));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

void write_png16(const std::filesystem::path& path, int width, int height, std::span<const float> rgba) {
    if (width <= 0 || height <= 0 || rgba.size() < size_t(width) * size_t(height) * 4)
        throw file_error(path.string(), "cannot write (pixel buffer smaller than the image)");
    const size_t row_bytes = size_t(width) * 6;
    std::vector<png_byte> bytes(row_bytes * size_t(height));
    for (size_t i = 0; i < size_t(width) * size_t(height); ++i)
        for (size_t c = 0; c < 3; ++c) {
            auto value = static_cast<uint16_t>(rt_linear_to_srgb(rgba[4 * i + c]) * 65535.0f + 0.5f);
            bytes[6 * i + 2 * c] = png_byte(value >> 8);  // PNG stores 16-bit samples big-endian
            bytes[6 * i + 2 * c + 1] = png_byte(value & 255u);
        }
    std::vector<png_bytep> rows(static_cast<size_t>(height));
    for (size_t y = 0; y < rows.size(); ++y) rows[y] = bytes.data() + y * row_bytes;
    std::string encoded, cause;
    if (!encode_png16(rows.data(), width, height, &encoded, &cause))
        throw file_error(path.string(),
                         "cannot write PNG (" + (cause.empty() ? std::string("encoder failed") : cause) + ")");
    write_file_atomically(path, encoded);
}

}  // namespace prism
