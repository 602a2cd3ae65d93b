// core/image_guard.h beyond the fuzz findings (tests/test_fuzz_findings.cpp): the formats Prism does not offer and
// the size limit, judged from headers alone so that nothing big is ever decoded.
#include "core/image_guard.h"

#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image_io.h"
#include "tests/test_support.h"

namespace {

std::vector<uint8_t> bytes_of(const std::string& text) { return std::vector<uint8_t>(text.begin(), text.end()); }

void put_be32(std::string& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xff);
}

// A PNG signature and an IHDR chunk claiming width x height (CRCs are not checked by stb): all a size check reads.
std::vector<uint8_t> png_header(uint32_t width, uint32_t height) {
    std::string png = "\x89PNG\r\n\x1a\n";
    put_be32(png, 13);
    png += "IHDR";
    put_be32(png, width);
    put_be32(png, height);
    png += std::string("\x08\x06\x00\x00\x00", 5);   // 8-bit RGBA, no interlace
    put_be32(png, 0);
    return bytes_of(png);
}

std::string guard_error(const std::vector<uint8_t>& bytes) {
    return prism::test::error_message([&] { prism::check_encoded_image(bytes, "/x/t.img"); });
}

}  // namespace

TEST(ImageGuard, RefusesFormatsPrismDoesNotOffer) {
    EXPECT_EQ(guard_error(bytes_of("GIF89a\x01\x00\x01\x00")),
              "/x/t.img: unsupported image format GIF (textures: PNG, JPEG, BMP, TGA or Radiance HDR)");
    EXPECT_NE(guard_error(bytes_of("8BPS\x00\x01")).find("Photoshop (PSD)"), std::string::npos);
    EXPECT_NE(guard_error(bytes_of("P6\n1 1\n255\n\x01\x02\x03")).find("PNM"), std::string::npos);
    EXPECT_NE(guard_error(bytes_of(std::string("\x53\x80\xf6\x34", 4) + std::string(100, 'x'))).find("Softimage PIC"),
              std::string::npos);
}

TEST(ImageGuard, RefusesImagesOverTheSizeLimitFromTheHeader) {
    EXPECT_EQ(guard_error(png_header(20000, 1)),
              "/x/t.img: image is 20000x1 pixels; Prism takes textures up to 16384 on a side and 64M pixels");
    EXPECT_NE(guard_error(png_header(16384, 8192)).find("16384x8192"), std::string::npos);   // 128M pixels
    EXPECT_EQ(guard_error(png_header(16384, 4096)), "(no prism::Error thrown)");                // 64M: allowed
    EXPECT_EQ(guard_error(png_header(8192, 8192)), "(no prism::Error thrown)");
}

TEST(ImageGuard, TexturesOverTheLimitFailWithoutDecoding) {
    // 16384x8192 is within stb_image's own limit (2^30 bytes), so it is the guard that stops it.
    const std::vector<uint8_t> claim = png_header(16384, 8192);
    const std::string message = prism::test::error_message(
        [&] { (void)prism::load_texture_from_memory(claim, "/x/huge.png"); });
    EXPECT_EQ(message.rfind("/x/huge.png: image is 16384x8192 pixels", 0), 0u) << message;
}
