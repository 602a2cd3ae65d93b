// Texture loading and render output: round trips, the real environment maps, and failures that leave no file.
#include "core/image/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>

#include <gtest/gtest.h>
#include <webp/encode.h>

#include "core/util/error.h"
#include "core/image/rgbe.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using test::error_message;

TEST(ImageIo, PngRoundTripKeepsEveryTexel) {
    const int width = 7, height = 5;
    std::vector<uint32_t> texels(width * height);
    std::mt19937 random(42);
    for (uint32_t& texel : texels) texel = random();
    std::filesystem::path path = test::temp_dir("image_io") / "round_trip.png";
    std::filesystem::remove(path);
    write_png(path, width, height, texels);
    Texture loaded = load_texture(path, false);
    EXPECT_EQ(loaded.width, width);
    EXPECT_EQ(loaded.height, height);
    EXPECT_EQ(loaded.encoding, TextureEncoding::Linear8);
    EXPECT_EQ(loaded.texels, texels);
    EXPECT_EQ(load_texture(path, true).encoding, TextureEncoding::Srgb8);
}

std::string webp_of(const std::vector<uint32_t>& rgba8, int width, int height, bool lossless) {
    uint8_t* encoded = nullptr;
    const auto* pixels = reinterpret_cast<const uint8_t*>(rgba8.data());
    const size_t size = lossless ? WebPEncodeLosslessRGBA(pixels, width, height, width * 4, &encoded)
                                 : WebPEncodeRGBA(pixels, width, height, width * 4, 90.0f, &encoded);
    std::string bytes(reinterpret_cast<const char*>(encoded), size);
    WebPFree(encoded);
    return bytes;
}

TEST(ImageIo, WebpLosslessKeepsEveryTexelAndLossyStaysClose) {
    const int width = 7, height = 5;
    std::vector<uint32_t> texels(width * height);
    std::mt19937 random(42);
    // Alpha kept above 0: the encoder drops the colour of fully transparent pixels unless told to keep it.
    for (uint32_t& texel : texels) texel = random() | 0x01000000u;
    Texture lossless = load_texture(test::write_file("lossless.webp", webp_of(texels, width, height, true)), false);
    EXPECT_EQ(lossless.width, width);
    EXPECT_EQ(lossless.height, height);
    EXPECT_EQ(lossless.encoding, TextureEncoding::Linear8);
    EXPECT_EQ(lossless.texels, texels);

    // A smooth gradient, opaque: lossy WebP keeps it within a few levels.
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            texels[y * width + x] = uint32_t(30 * x) | uint32_t(40 * y) << 8 | 128u << 16 | 255u << 24;
    Texture lossy = load_texture(test::write_file("lossy.webp", webp_of(texels, width, height, false)), true);
    EXPECT_EQ(lossy.encoding, TextureEncoding::Srgb8);
    ASSERT_EQ(lossy.texels.size(), texels.size());
    int worst = 0;
    for (size_t i = 0; i < texels.size(); ++i)
        for (int shift = 0; shift < 32; shift += 8)
            worst = std::max(worst, std::abs(int(lossy.texels[i] >> shift & 255) - int(texels[i] >> shift & 255)));
    EXPECT_LE(worst, 24);
}

TEST(ImageIo, BrokenOrHugeWebpIsNamedInOneLine) {
    std::vector<uint32_t> texels(64 * 64, 0xff336699u);
    const std::string webp = webp_of(texels, 64, 64, true);
    auto error_of = [](const std::string& name, const std::string& bytes) {
        const std::filesystem::path path = test::write_file(name, bytes);
        const std::string message = error_message([&] { load_texture(path); });
        EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    };
    EXPECT_NE(error_of("truncated.webp", webp.substr(0, webp.size() / 2)).find("WebP"), std::string::npos);
    EXPECT_NE(error_of("header.webp", webp.substr(0, 14)).find("corrupt WebP"), std::string::npos);
    // A lossless header declaring 16384 x 16384 pixels over no data: refused from the header, nothing allocated.
    ASSERT_EQ(webp.substr(12, 4), "VP8L");
    std::string huge = webp.substr(0, 21);  // RIFF header, VP8L chunk header, the lossless signature byte
    const uint32_t bits = (16384u - 1) | (16384u - 1) << 14;  // width - 1, height - 1; no alpha, version 0
    huge.append(reinterpret_cast<const char*>(&bits), 4);
    EXPECT_NE(error_of("huge.webp", huge).find("image is 16384x16384 pixels"), std::string::npos);
}

TEST(ImageIo, RgbePackUnpackWithinOnePercent) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> exponent(-20.0f, 20.0f), fraction(0.0f, 1.0f);
    for (int i = 0; i < 10000; ++i) {
        float scale = std::exp2(exponent(random));
        glm::vec3 color(fraction(random), fraction(random), fraction(random));
        color *= scale;
        glm::vec3 back = unpack_rgbe(pack_rgbe(color));
        float largest = std::max(color.x, std::max(color.y, color.z));
        for (int c = 0; c < 3; ++c) {  // shared exponent: the error is relative to the brightest channel
            ASSERT_LE(std::abs(back[c] - color[c]), 0.01f * largest) << "channel " << c << " of " << i;
            ASSERT_LE(std::abs(back[c] - color[c]), largest / 256.0f) << "half a step of the largest mantissa";
        }
    }
    EXPECT_EQ(pack_rgbe(glm::vec3(0.0f)), 0u);
    EXPECT_EQ(unpack_rgbe(0u), glm::vec3(0.0f));
    // Ward's layout: 1.0 is mantissa 128 with exponent byte 129.
    EXPECT_EQ(pack_rgbe(glm::vec3(1.0f, 0.5f, 0.0f)), 128u | (64u << 8) | (0u << 16) | (129u << 24));
    // Decoding takes the middle of the truncated step (as kernels/texture.h does): within half a step.
    EXPECT_NEAR(unpack_rgbe(pack_rgbe(glm::vec3(0.9999f))).x, 0.9999f, 0.5f / 256.0f);
    EXPECT_EQ(pack_rgbe(glm::vec3(-1.0f, NAN, 0.0f)), 0u);
    EXPECT_EQ(pack_rgbe(glm::vec3(INFINITY, 1.0f, 0.0f)) >> 24, 255u) << "saturates";
}

TEST(ImageIo, HdrRoundTripKeepsValues) {
    const int width = 4, height = 3;
    std::vector<float> rgba;
    for (int i = 0; i < width * height; ++i) rgba.insert(rgba.end(), {0.1f * i, 2.0f, 100.0f + i, 1.0f});
    std::filesystem::path path = test::temp_dir("image_io") / "round_trip.HDR";
    check_output_extension(path);
    write_hdr(path, width, height, rgba);
    Texture loaded = load_texture(path);
    ASSERT_EQ(loaded.encoding, TextureEncoding::Rgbe);
    ASSERT_EQ(loaded.texels.size(), size_t(width * height));
    for (int i = 0; i < width * height; ++i) {
        glm::vec3 value = unpack_rgbe(loaded.texels[i]);
        EXPECT_NEAR(value.y, 2.0f, 0.02f * (100.0f + i));
        EXPECT_NEAR(value.z, 100.0f + i, 0.01f * (100.0f + i));
    }
}

// A file of ../shared/scenes, loaded and checked for its size and encoding (all texels there).
Texture load_real_texture(const std::string& name, int width, int height, TextureEncoding encoding) {
    Texture texture = load_texture(test::scene(name));
    EXPECT_EQ(texture.width, width);
    EXPECT_EQ(texture.height, height);
    EXPECT_EQ(texture.encoding, encoding);
    EXPECT_EQ(texture.texels.size(), size_t(width) * size_t(height));
    texture.texels.resize(size_t(width) * size_t(height));  // the checks below read every texel
    return texture;
}

TEST(ImageIo, LoadsRealEquirectHdr) {
    Texture texture = load_real_texture("env/venice_sunset_1k.hdr", 1024, 512, TextureEncoding::Rgbe);
    // A sunset sky is bright somewhere and never all black.
    float brightest = 0.0f;
    for (uint32_t texel : texture.texels) {
        glm::vec3 value = unpack_rgbe(texel);
        ASSERT_TRUE(std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z));
        brightest = std::max(brightest, std::max(value.x, std::max(value.y, value.z)));
    }
    EXPECT_GT(brightest, 1.0f);
    EXPECT_EQ(load_texture(test::scene("env/studio_small_03_1k.hdr")).width, 1024);
}

TEST(ImageIo, LoadsRealCubeMapFace) {
    Texture face = load_real_texture("env/cubemap-miramar/right.png", 1024, 1024, TextureEncoding::Srgb8);
    EXPECT_EQ(face.texels[0] >> 24, 255u) << "faces have no alpha channel: stb fills it opaque";
}

TEST(ImageIo, CorruptPngNamesTheFile) {
    std::string png = "\x89PNG\r\n\x1a\n";
    png += std::string("\0\0\0\rIHDR\0\0\0\x10\0\0\0\x10\x08\x06\0\0\0", 21);
    png += "garbage that is not a CRC nor an IDAT chunk";
    std::filesystem::path path = test::write_file("corrupt.png", png);
    std::string message = error_message([&] { load_texture(path); });
    EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
    std::filesystem::path noise = test::write_file("noise.jpg", std::string(300, '\x5a'));
    message = error_message([&] { load_texture(noise); });
    EXPECT_EQ(message.rfind(noise.string() + ": ", 0), 0u) << message;
    std::filesystem::path missing = test::temp_dir("image_io") / "no_such_texture.png";
    message = error_message([&] { load_texture(missing); });
    EXPECT_EQ(message.rfind(missing.string() + ": ", 0), 0u) << message;
}

TEST(ImageIo, UnwritablePathThrowsAndLeavesNoFile) {
    std::filesystem::path directory = test::temp_dir("image_io") / "missing_directory";
    std::filesystem::remove_all(directory);
    std::filesystem::path path = directory / "out.png";
    std::vector<uint32_t> texels(4, 0xff00ff00u);
    std::string message = error_message([&] { write_png(path, 2, 2, texels); });
    EXPECT_EQ(message.rfind(path.string() + ": cannot write (", 0), 0u) << message;
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(directory));

    // A directory in the way of the final name: the rename fails and the temporary file is cleaned up.
    std::filesystem::path blocked = test::temp_dir("image_io") / "blocked.hdr";
    std::filesystem::remove_all(blocked);
    std::filesystem::create_directories(blocked / "child");
    std::vector<float> rgba(16, 1.0f);
    message = error_message([&] { write_hdr(blocked, 2, 2, rgba); });
    EXPECT_EQ(message.rfind(blocked.string() + ": cannot write (", 0), 0u) << message;
    for (const auto& entry : std::filesystem::directory_iterator(blocked.parent_path()))
        EXPECT_EQ(entry.path().filename().string().find("blocked.hdr.tmp-"), std::string::npos) << entry.path();
}

TEST(ImageIo, OutputExtensionIsChecked) {
    check_output_extension("render.png");
    check_output_extension("render.PNG");
    check_output_extension("dir/render.Hdr");
    EXPECT_EQ(error_message([] { check_output_extension("render.jpg"); }),
              "render.jpg: unsupported output format '.jpg' (use .png or .hdr)");
    EXPECT_EQ(error_message([] { check_output_extension("render"); }),
              "render: unsupported output format '' (use .png or .hdr)");
}

TEST(ImageIo, FindsFilesIgnoringCase) {
    std::filesystem::path sponza = test::scene("mcguire/dabrovic-sponza");
    std::filesystem::path found = find_file_case_insensitive(sponza, "kamen.jpg");
    EXPECT_EQ(found.filename(), "KAMEN.JPG");
    EXPECT_EQ(find_file_case_insensitive(sponza, "KAMEN.JPG").filename(), "KAMEN.JPG");
    EXPECT_TRUE(find_file_case_insensitive(sponza, "no_such_file.jpg").empty());
    // Windows-style separators and a differently-cased folder.
    std::filesystem::path root = test::temp_dir("image_io") / "case";
    std::filesystem::create_directories(root / "Textures");
    std::filesystem::path target = root / "Textures" / "Wall.PNG";
    { std::ofstream(target) << "x"; }
    EXPECT_EQ(find_file_case_insensitive(root, "textures\\wall.png"), target);
    EXPECT_EQ(find_file_case_insensitive(root, "./TEXTURES/wall.png"), target);
    EXPECT_TRUE(find_file_case_insensitive(root, "textures").empty()) << "a directory is not a texture";
}

}  // namespace
}  // namespace prism
