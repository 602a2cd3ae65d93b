// The resolve stage's display transform (kernels/display.h): exposure in stops on every output, and the Khronos PBR
// Neutral tone map for the image. Its agreement across backends is an Agreement case (test_backend_contract.cpp).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "core/render/render_engine.h"
#include "kernels/display.h"
#include "kernels/texture.h"
#include "tests/test_support.h"

namespace prism {
namespace {

float3 neutral(float r, float g, float b) { return rt_tone_map_neutral(make_float3(r, g, b)); }

// Below the compression's start the tone map only subtracts its toe offset (0.04 once the darkest channel passes
// 0.08); above it the brightest channel approaches 1 without reaching it, in order, and a saturated colour fades
// towards white as it does.
TEST(DisplayTransform, NeutralToneMapKeepsMidtonesAndRollsOffHighlights) {
    float3 mid = neutral(0.5f, 0.3f, 0.2f);
    EXPECT_FLOAT_EQ(mid.x, 0.46f);
    EXPECT_FLOAT_EQ(mid.y, 0.26f);
    EXPECT_FLOAT_EQ(mid.z, 0.16f);
    float3 black = neutral(0.0f, 0.0f, 0.0f);
    EXPECT_EQ(black.x, 0.0f);
    float previous = 0.0f;
    for (float peak : {0.8f, 1.0f, 2.0f, 8.0f, 64.0f}) {
        float3 c = neutral(peak, peak * 0.5f, peak * 0.25f);
        EXPECT_LT(c.x, 1.0f) << peak;
        EXPECT_GT(c.x, previous) << peak;
        EXPECT_GT(c.x, c.y) << peak;
        EXPECT_GT(c.y, c.z) << peak;
        previous = c.x;
    }
    float3 bright = neutral(8.0f, 4.0f, 2.0f), brighter = neutral(64.0f, 32.0f, 16.0f);
    EXPECT_GT(brighter.z / brighter.x, bright.z / bright.x);  // desaturated towards white
    float3 same = rt_display_color(make_float3(3.0f, 2.0f, 1.0f), false);
    EXPECT_EQ(same.x, 3.0f);
}

FrameResult render_sphere(float exposure, ToneMap tone_map) {
    struct Loaded {
        Scene scene;
        DeviceScene device;
    };
    static const Loaded sphere = [] {
        Loaded loaded;
        loaded.device = test::load_device_scene("builtin:sphere", &loaded.scene, BvhLayout::Wide);
        return loaded;
    }();
    RenderSettings settings = test::small_settings(64, 48, 4);
    settings.read_radiance = true;
    settings.exposure = exposure;
    settings.tone_map = tone_map;
    return RenderEngine("cpu-ref", sphere.device).render(sphere.scene.camera, settings);
}

// A stop is a factor of two on the radiance (exactly: a power of two), so on what .exr and .hdr files hold; no
// stop leaves the light as traced. The tone map keeps the image's highlights off the clip.
TEST(DisplayTransform, ExposureScalesTheRadianceAndToneMapKeepsHighlights) {
    FrameResult plain = render_sphere(0.0f, ToneMap::None);
    FrameResult brighter = render_sphere(1.0f, ToneMap::None);
    FrameResult darker = render_sphere(-2.0f, ToneMap::None);
    ASSERT_EQ(plain.radiance.size(), brighter.radiance.size());
    size_t lit = 0;
    for (size_t i = 0; i < plain.radiance.size(); i += 4) {
        for (size_t c = 0; c < 3; ++c) {
            EXPECT_EQ(brighter.radiance[i + c], 2.0f * plain.radiance[i + c]);
            EXPECT_EQ(darker.radiance[i + c], 0.25f * plain.radiance[i + c]);
        }
        lit += plain.radiance[i] > 0.05f;
    }
    EXPECT_GT(lit, plain.radiance.size() / 8);

    auto clipped = [](const FrameResult& frame) {
        return std::count_if(frame.image.begin(), frame.image.end(), [](uint32_t p) {
            return (p & 255u) == 255u || ((p >> 8) & 255u) == 255u || ((p >> 16) & 255u) == 255u;
        });
    };
    FrameResult hot = render_sphere(3.0f, ToneMap::None);
    FrameResult mapped = render_sphere(3.0f, ToneMap::Neutral);
    EXPECT_GT(clipped(hot), long(hot.image.size() / 10));
    EXPECT_LT(clipped(mapped), clipped(hot) / 10);
    // The image is the radiance in sRGB: with the tone map, the radiance holds the tone-mapped values.
    for (size_t i = 0; i < mapped.image.size(); i += 97)
        EXPECT_EQ(mapped.image[i] & 255u, uint32_t(rt_linear_to_srgb(mapped.radiance[4 * i]) * 255.0f + 0.5f));
}

}  // namespace
}  // namespace prism
