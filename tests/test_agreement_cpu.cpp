// The `cpu` wavefront backend against the `cpu-ref` recursive oracle: same kernels/ functions, different
// scheduling (device-style queues, atomic appends, weights carried by rays). Accumulation is exact fixed point, so
// the images are expected to be identical; the requirement is PSNR >= 50 dB.
#include <gtest/gtest.h>

#include "core/render_engine.h"
#include "core/scene_loader.h"
#include "tests/test_support.h"

namespace {

struct Case {
    std::string scene;
    uint32_t width, height, depth;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

class CpuAgreement : public ::testing::TestWithParam<Case> {};

prism::DeviceScene load(const std::string& spec, prism::BvhLayout layout = prism::BvhLayout::Stack,
                        prism::BvhMethod method = prism::BvhMethod::BinnedSah, prism::Scene* out = nullptr) {
    prism::LoadOptions options;
    options.data_dir = prism::test::scenes_dir();
    prism::Scene scene = prism::load_scene(spec, options);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    bvh.method = method;
    prism::DeviceScene device = prism::build_device_scene(scene, bvh);
    if (out) *out = std::move(scene);
    return device;
}

std::string resolve(const std::string& spec) {
    return spec.rfind("builtin:", 0) == 0 ? spec : prism::test::scene(spec).string();
}

}  // namespace

TEST_P(CpuAgreement, WavefrontMatchesRecursiveReference) {
    const Case& c = GetParam();
    prism::Scene scene;
    prism::DeviceScene device = load(resolve(c.scene), prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::RenderSettings settings;
    settings.width = c.width;
    settings.height = c.height;
    settings.max_depth = c.depth;
    prism::RenderEngine reference("cpu-ref", device);
    prism::RenderEngine wavefront("cpu", device);
    prism::FrameResult expected = reference.render(scene.camera, settings);
    prism::FrameResult actual = wavefront.render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    EXPECT_EQ(expected.stats.rays_per_depth, actual.stats.rays_per_depth);
    EXPECT_EQ(expected.stats.shadow_rays_per_depth, actual.stats.shadow_rays_per_depth);
    EXPECT_EQ(actual.stats.regrows, 0u) << "the default queue size should fit these scenes";
    // Not a black or flat image: the scene is actually visible.
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, CpuAgreement,
    ::testing::Values(Case{"builtin:sphere", 160, 120, 8}, Case{"builtin:bunny", 160, 120, 6},
                      Case{"builtin:dragon", 128, 96, 6}, Case{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 128, 128, 6},
                      Case{"gltf/TransmissionTest/TransmissionTest.glb", 128, 96, 6},
                      Case{"gltf/BoxTextured/BoxTextured.glb", 96, 96, 4},
                      Case{"gltf/OrientationTest/OrientationTest.glb", 128, 96, 4},
                      Case{"gltf/DamagedHelmet/DamagedHelmet.glb", 96, 96, 4},
                      Case{"gltf/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.glb", 128, 96, 4}),
    [](const ::testing::TestParamInfo<Case>& info) {
        std::string name = info.param.scene.substr(info.param.scene.find_last_of(":/") + 1);
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
        return name;
    });

// Both node layouts and both builders trace the same closest hits, so they render the same image.
TEST(CpuAgreement, LayoutsAndBuildersRenderTheSameImage) {
    prism::Scene scene;
    prism::DeviceScene stack = load("builtin:sphere", prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::DeviceScene escape = load("builtin:sphere", prism::BvhLayout::Escape, prism::BvhMethod::Median);
    prism::RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    prism::FrameResult a = prism::RenderEngine("cpu", stack).render(scene.camera, settings);
    prism::FrameResult b = prism::RenderEngine("cpu", escape).render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(a.image, b.image), 50.0);
}

// Issue 8's determinism: the same frame twice is bit-identical (exact accumulation, deterministic BVH).
TEST(CpuAgreement, RenderingIsDeterministic) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    prism::RenderEngine engine("cpu", device);
    EXPECT_EQ(engine.render(scene.camera, settings).image, engine.render(scene.camera, settings).image);
}

// A tiny queue forces the renderer to grow it and re-run: no ray may be lost.
TEST(CpuAgreement, OverflowingQueuesAreGrownNotDropped) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
    settings.queue_factor = 1.0f;
    prism::FrameResult actual = prism::RenderEngine("cpu", device).render(scene.camera, settings);
    EXPECT_EQ(expected.image, actual.image);
}
