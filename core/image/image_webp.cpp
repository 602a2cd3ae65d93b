#include "core/image/image_webp.h"

#include <webp/decode.h>

#include <cstring>
#include <memory>

#include "core/image/image_guard.h"
#include "core/util/error.h"
#include "core/util/scene_read_rules.h"

namespace prism {
namespace {

struct WebpFree {
    void operator()(uint8_t* pixels) const { WebPFree(pixels); }
};

}  // namespace

bool is_webp(std::span<const uint8_t> bytes) {
    return bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 &&
           std::memcmp(bytes.data() + 8, "WEBP", 4) == 0;
}

Rgba8Pixels decode_webp(std::span<const uint8_t> bytes, const std::string& name) {
    WebPBitstreamFeatures features;
    if (WebPGetFeatures(bytes.data(), bytes.size(), &features) != VP8_STATUS_OK)
        throw file_error(name, "corrupt WebP (its header does not read)");
    if (features.has_animation) throw file_error(name, "animated WebP is not supported (textures are still images)");
    check_texture_dimensions(name, features.width, features.height);
    charge_texture_bytes(name, uint64_t(features.width) * uint64_t(features.height) * 4);
    Rgba8Pixels pixels;
    std::unique_ptr<uint8_t, WebpFree> decoded(
        WebPDecodeRGBA(bytes.data(), bytes.size(), &pixels.width, &pixels.height));
    if (!decoded) throw file_error(name, "corrupt or truncated WebP (the image data do not decode)");
    pixels.rgba.assign(decoded.get(), decoded.get() + size_t(pixels.width) * size_t(pixels.height) * 4);
    return pixels;
}

}  // namespace prism
