// The gate every encoded image passes before stb_image decodes it (textures, cube-map faces, equirect maps,
// embedded glTF images). Debian 12's stb_image (2.27) is older than upstream's security fixes, and the fuzzers
// (fuzz/fuzz_image.cpp) drive it into out-of-bounds accesses; Prism must not hand it bytes it cannot survive.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace prism {

// Textures larger than this are refused before decoding: a few hundred bytes of header must not make Prism
// allocate gigabytes (8192x8192, or 16384x4096; lavapipe's storage buffers end at 128 MiB anyway).
constexpr int kMaxTextureSide = 16384;
constexpr int64_t kMaxTexturePixels = int64_t(1) << 26;

// Throws prism::Error "<name>: <cause>" when a width x height image exceeds the limits above.
void check_texture_dimensions(const std::string& name, int64_t width, int64_t height);

// Throws prism::Error "<name>: <cause>" for an image Prism does not take: a format other than PNG, JPEG, BMP,
// TGA and Radiance HDR (WebP goes to libwebp instead, image_webp.h) (stb_image would also decode GIF, PSD, PIC and
// PNM), a size over the limits above, a file too short for the pixels its header declares (stb would fill them with
// zeros, or spin), or a structure Debian's stb_image mishandles (image_guard_formats.h; each case has its test in
// tests/test_fuzz_findings.cpp).
void check_encoded_image(std::span<const uint8_t> bytes, const std::string& name);

}  // namespace prism
