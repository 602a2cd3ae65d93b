#include "core/image/image_guard.h"

#include <climits>
#include <cstring>
#include <string_view>

#include <stb_image.h>

#include "core/util/error.h"
#include "core/image/image_guard_formats.h"

namespace prism {
namespace {

bool starts_with(std::span<const uint8_t> bytes, std::string_view prefix) {
    return bytes.size() >= prefix.size() && std::memcmp(bytes.data(), prefix.data(), prefix.size()) == 0;
}

// stb_image tries its decoders in turn; these are the signatures of the ones Prism does not offer.
const char* unsupported_format(std::span<const uint8_t> bytes) {
    if (starts_with(bytes, "GIF8")) return "GIF";
    if (starts_with(bytes, "8BPS")) return "Photoshop (PSD)";
    if (starts_with(bytes, "\x53\x80\xf6\x34")) return "Softimage PIC";
    if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '6')) return "PNM";
    return nullptr;
}

}  // namespace

void check_texture_dimensions(const std::string& name, int64_t width, int64_t height) {
    if (width > kMaxTextureSide || height > kMaxTextureSide || width * height > kMaxTexturePixels)
        throw file_error(name, "image is " + std::to_string(width) + "x" + std::to_string(height) +
                                   " pixels; Prism takes textures up to " + std::to_string(kMaxTextureSide) +
                                   " on a side and " + std::to_string(kMaxTexturePixels >> 20) + "M pixels");
}

void check_encoded_image(std::span<const uint8_t> bytes, const std::string& name) {
    using namespace image_guard;
    if (const char* format = unsupported_format(bytes))
        throw file_error(name, std::string("unsupported image format ") + format +
                                   " (textures: PNG, JPEG, WebP, BMP, TGA or Radiance HDR)");
    const bool jpeg = jpeg_start_of_image(bytes) != 0, png = starts_with(bytes, "\x89PNG\r\n\x1a\n");
    const bool hdr = starts_with(bytes, "#?RADIANCE\n") || starts_with(bytes, "#?RGBE\n"),
               bmp = starts_with(bytes, "BM");
    if (jpeg) check_jpeg(bytes, name);  // before stbi_info, which parses the tables too
    if (png) check_png(bytes, name);
    if (bytes.size() > size_t(INT_MAX)) throw file_error(name, "image file too large");
    int width = 0, height = 0, channels = 0;
    // stbi_info reads headers only; images it cannot size fail in the decoder with stb's own reason.
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels)) return;
    // A BMP stored top down declares a negative height; stbi_info passes it on, while the decoder takes its
    // magnitude, so the limits below must see the magnitude too.
    if (bmp && height < 0 && height != INT_MIN) height = -height;
    check_texture_dimensions(name, width, height);
    if (width <= 0 || height <= 0) return;  // stb refuses it
    // Whether the file can hold what its header declares. A file stb sizes that has none of the other signatures
    // is a TGA (stb tries TGA last; it has no signature, and its header rules out the others' first bytes).
    if (jpeg)
        check_jpeg_size(bytes, name, width, height);
    else if (hdr)
        check_hdr(bytes, name, width, height);
    else if (bmp)
        check_bmp(bytes, name, width, height);
    else if (!png)
        check_tga(bytes, name, width, height);
}

}  // namespace prism
