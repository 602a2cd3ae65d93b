// core/image/image_guard.h beyond the fuzz findings (tests/test_fuzz_findings.cpp): the formats Prism does not offer
// and the size limit, judged from headers alone so that nothing big is ever decoded.
#include "core/image/image_guard.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "core/util/error.h"
#include "core/image/image_io.h"
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
    png += std::string("\x08\x06\x00\x00\x00", 5);  // 8-bit RGBA, no interlace
    put_be32(png, 0);
    return bytes_of(png);
}

std::string guard_error(const std::vector<uint8_t>& bytes) {
    return prism::test::error_message([&] { prism::check_encoded_image(bytes, "/x/t.img"); });
}

}  // namespace

TEST(ImageGuard, RefusesFormatsPrismDoesNotOffer) {
    EXPECT_EQ(guard_error(bytes_of("GIF89a\x01\x00\x01\x00")),
              "/x/t.img: unsupported image format GIF (textures: PNG, JPEG, WebP, BMP, TGA or Radiance HDR)");
    EXPECT_NE(guard_error(bytes_of("8BPS\x00\x01")).find("Photoshop (PSD)"), std::string::npos);
    EXPECT_NE(guard_error(bytes_of("P6\n1 1\n255\n\x01\x02\x03")).find("PNM"), std::string::npos);
    EXPECT_NE(guard_error(bytes_of(std::string("\x53\x80\xf6\x34", 4) + std::string(100, 'x'))).find("Softimage PIC"),
              std::string::npos);
}

// JPEG frame types stb_image does not decode are named as unsupported, not corrupt (libjpeg-turbo's testimages:
// testimgari.jpg is arithmetic-coded, monkey12.jpg has 12-bit samples).
TEST(ImageGuard, JpegFramesStbCannotDecodeAreNamedAsUnsupported) {
    // SOI, then a frame header: marker, length 11, precision, 1x1 pixels, one component.
    auto jpeg_with_frame = [](uint8_t marker, uint8_t precision) {
        return bytes_of(std::string("\xff\xd8\xff", 3) + char(marker) + std::string("\x00\x0b", 2) + char(precision) +
                        std::string("\x00\x01\x00\x01\x01\x01\x11\x00\xff\xd9", 10));
    };
    EXPECT_EQ(guard_error(jpeg_with_frame(0xc9, 8)),
              "/x/t.img: arithmetic-coded JPEG is not supported (textures: baseline or progressive, Huffman-coded)");
    EXPECT_NE(guard_error(jpeg_with_frame(0xc3, 8)).find("lossless JPEG"), std::string::npos);
    EXPECT_NE(guard_error(jpeg_with_frame(0xc5, 8)).find("hierarchical JPEG"), std::string::npos);
    EXPECT_EQ(guard_error(jpeg_with_frame(0xc0, 12)), "/x/t.img: 12-bit JPEG is not supported (8-bit samples only)");
    EXPECT_EQ(guard_error(jpeg_with_frame(0xc2, 8)), "(no prism::Error thrown)");  // progressive: stb decodes it
}

TEST(ImageGuard, RefusesImagesOverTheSizeLimitFromTheHeader) {
    EXPECT_EQ(guard_error(png_header(20000, 1)),
              "/x/t.img: image is 20000x1 pixels; Prism takes textures up to 16384 on a side and 64M pixels");
    EXPECT_NE(guard_error(png_header(16384, 8192)).find("16384x8192"), std::string::npos);  // 128M pixels
    EXPECT_EQ(guard_error(png_header(16384, 4096)), "(no prism::Error thrown)");            // 64M: allowed
    EXPECT_EQ(guard_error(png_header(8192, 8192)), "(no prism::Error thrown)");
}

TEST(ImageGuard, TexturesOverTheLimitFailWithoutDecoding) {
    // 16384x8192 is within stb_image's own limit (2^30 bytes), so it is the guard that stops it.
    const std::vector<uint8_t> claim = png_header(16384, 8192);
    const std::string message =
        prism::test::error_message([&] { (void)prism::load_texture_from_memory(claim, "/x/huge.png"); });
    EXPECT_EQ(message.rfind("/x/huge.png: image is 16384x8192 pixels", 0), 0u) << message;
}

// The truncation checks must pass complete files: TGA (stb writes run-length TGA), BMP and HDR as stb writes them
// load. BMP and HDR data cut by a few bytes is refused (their size is exact: rows, or the run-length walk); a
// run-length TGA only when shorter than its most compact encoding could be (here: the header alone).
TEST(ImageGuard, CompleteTgaBmpAndHdrPassAndCutOnesDoNot) {
    const int width = 16, height = 8;
    std::vector<uint8_t> rgba(width * height * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<uint8_t>(i * 37);
    std::vector<float> rgb(width * height * 3, 0.25f);
    const std::filesystem::path dir = prism::test::temp_dir("image_guard");
    ASSERT_TRUE(stbi_write_tga((dir / "a.tga").c_str(), width, height, 4, rgba.data()));
    ASSERT_TRUE(stbi_write_bmp((dir / "a.bmp").c_str(), width, height, 4, rgba.data()));
    ASSERT_TRUE(stbi_write_hdr((dir / "a.hdr").c_str(), width, height, 3, rgb.data()));
    for (const char* name : {"a.tga", "a.bmp", "a.hdr"}) {
        const prism::Texture texture = prism::load_texture(dir / name);
        EXPECT_EQ(texture.width, width) << name;
        EXPECT_EQ(texture.height, height) << name;
    }
    for (const auto& [name, keep] : {std::pair<const char*, long>{"a.tga", 18}, {"a.bmp", -5}, {"a.hdr", -5}}) {
        std::ifstream in(dir / name, std::ios::binary);
        std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        bytes.resize(keep > 0 ? size_t(keep) : bytes.size() - size_t(-keep));
        const std::string message = guard_error(bytes);
        EXPECT_EQ(message.rfind("/x/t.img: truncated ", 0), 0u) << name << ": " << message;
    }
}
