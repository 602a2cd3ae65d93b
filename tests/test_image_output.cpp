// Render outputs read back with independent decoders: OpenEXR through tinyexr's LoadEXR (values above 1 kept),
// 16-bit PNG through stb_image's 16-bit loader, and the choice of format by extension and --png-depth.
#include "core/image/image_output.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <set>

#include <gtest/gtest.h>
#include <stb_image.h>
#include <tinyexr.h>

#include "core/util/error.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using test::error_message;

// A gradient from black to far above 1 (the radiance of a light seen directly is not clamped).
std::vector<float> gradient(int width, int height) {
    std::vector<float> rgba;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            rgba.insert(rgba.end(),
                        {0.25f * float(x), 0.01f * float(y), 1000.0f * float(x + y) / float(width + height), 1.0f});
    return rgba;
}

float srgb(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? linear * 12.92f : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

TEST(ImageOutput, ExrKeepsLinearValuesAboveOneAsHalfFloats) {
    const int width = 19, height = 11;
    std::vector<float> rgba = gradient(width, height);
    std::filesystem::path path = test::temp_dir("image_output") / "gradient.exr";
    std::filesystem::remove(path);
    write_exr(path, width, height, rgba);

    float* loaded = nullptr;
    int loaded_width = 0, loaded_height = 0;
    const char* error = nullptr;
    ASSERT_EQ(LoadEXR(&loaded, &loaded_width, &loaded_height, path.c_str(), &error), TINYEXR_SUCCESS)
        << (error ? error : "");
    std::unique_ptr<float, decltype(&std::free)> owned(loaded, &std::free);
    ASSERT_EQ(loaded_width, width);
    ASSERT_EQ(loaded_height, height);
    float largest = 0.0f;
    for (size_t i = 0; i < size_t(width * height); ++i)
        for (size_t c = 0; c < 3; ++c) {
            float expected = rgba[4 * i + c];
            // Half floats: 11 significant bits.
            ASSERT_NEAR(loaded[4 * i + c], expected, std::abs(expected) / 1024.0f + 1e-6f)
                << "pixel " << i << " channel " << c;
            largest = std::max(largest, loaded[4 * i + c]);
        }
    EXPECT_GT(largest, 900.0f) << "values above 1 must survive";

    EXRVersion version;
    ASSERT_EQ(ParseEXRVersionFromFile(&version, path.c_str()), TINYEXR_SUCCESS);
    EXRHeader header;
    InitEXRHeader(&header);
    ASSERT_EQ(ParseEXRHeaderFromFile(&header, &version, path.c_str(), &error), TINYEXR_SUCCESS);
    ASSERT_EQ(header.num_channels, 3);
    for (int c = 0; c < header.num_channels; ++c) EXPECT_EQ(header.pixel_types[c], TINYEXR_PIXELTYPE_HALF);
    FreeEXRHeader(&header);
}

TEST(ImageOutput, Png16IsSrgbEncodedWithSixteenBitSteps) {
    const int width = 23, height = 7;
    std::vector<float> rgba;
    for (int i = 0; i < width * height; ++i) {
        float t = float(i) / float(width * height - 1);
        rgba.insert(rgba.end(), {t, t * t, 4.0f * t, 1.0f});  // blue goes above 1 and clips, as in 8-bit PNG
    }
    std::filesystem::path path = test::temp_dir("image_output") / "ramp16.png";
    std::filesystem::remove(path);
    write_png16(path, width, height, rgba);

    ASSERT_TRUE(stbi_is_16_bit(path.c_str()));
    int loaded_width = 0, loaded_height = 0, channels = 0;
    std::unique_ptr<uint16_t, decltype(&stbi_image_free)> loaded(
        stbi_load_16(path.c_str(), &loaded_width, &loaded_height, &channels, 3), &stbi_image_free);
    ASSERT_TRUE(loaded) << stbi_failure_reason();
    ASSERT_EQ(loaded_width, width);
    ASSERT_EQ(loaded_height, height);
    EXPECT_EQ(channels, 3);
    std::set<uint16_t> distinct;
    for (size_t i = 0; i < size_t(width * height); ++i)
        for (size_t c = 0; c < 3; ++c) {
            uint16_t value = loaded.get()[3 * i + c];
            EXPECT_NEAR(value, srgb(rgba[4 * i + c]) * 65535.0f, 1.0f) << "pixel " << i << " channel " << c;
            if (c == 0) distinct.insert(value);
        }
    EXPECT_EQ(distinct.size(), size_t(width * height)) << "a 16-bit ramp keeps every step apart";
    EXPECT_EQ(loaded.get()[3 * (width * height - 1) + 2], 65535u);
}

TEST(ImageOutput, FormatFollowsExtensionAndPngDepth) {
    EXPECT_EQ(output_image_format("a.png"), ImageFormat::Png8);
    EXPECT_EQ(output_image_format("a.PNG", 16), ImageFormat::Png16);
    EXPECT_EQ(output_image_format("dir/a.exr"), ImageFormat::Exr);
    EXPECT_EQ(output_image_format("a.Hdr"), ImageFormat::Hdr);
    EXPECT_TRUE(needs_linear_radiance(ImageFormat::Exr));
    EXPECT_TRUE(needs_linear_radiance(ImageFormat::Png16));
    EXPECT_FALSE(needs_linear_radiance(ImageFormat::Png8));
    EXPECT_EQ(error_message([] { output_image_format("a.tif"); }),
              "a.tif: unsupported output format '.tif' (use .png, .exr or .hdr)");
    EXPECT_EQ(error_message([] { output_image_format("a.exr", 16); }),
              "a.exr: --png-depth applies to .png output only, not '.exr'");
    EXPECT_NE(error_message([] { output_image_format("a.png", 12); }).find("--png-depth"), std::string::npos);
}

TEST(ImageOutput, FailedWritesLeaveNoFile) {
    std::vector<float> rgba = gradient(4, 4);
    std::filesystem::path blocked = test::temp_dir("image_output") / "no-such-folder" / "x.exr";
    EXPECT_NE(error_message([&] { write_exr(blocked, 4, 4, rgba); }).find("x.exr"), std::string::npos);
    EXPECT_NE(error_message([&] { write_png16(blocked.replace_extension(".png"), 4, 4, rgba); }).find("x.png"),
              std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(blocked.parent_path()));
    EXPECT_NE(error_message([&] { write_exr("small.exr", 4, 4, std::span(rgba).first(10)); }).find("small.exr"),
              std::string::npos);
}

}  // namespace
}  // namespace prism
