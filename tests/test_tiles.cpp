// Rendering a frame as tiles (RenderSettings::region, the kernels' FrameParams::tile_*): the tiles cover the image
// once, and the assembled tiles equal the whole frame bit for bit on every backend this machine runs.
#include <gtest/gtest.h>

#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "core/render/tiles.h"
#include "tests/test_support.h"

namespace {

TEST(Tiles, CoverTheImageExactlyOnce) {
    for (uint32_t tile_size : {1u, 7u, 16u, 64u, 200u}) {
        const uint32_t width = 45, height = 31;
        std::vector<int> covered(width * height, 0);
        for (const prism::PixelRect& t : prism::split_into_tiles(width, height, tile_size)) {
            EXPECT_LE(t.width, tile_size);
            EXPECT_LE(t.height, tile_size);
            for (uint32_t y = t.y; y < t.y + t.height; ++y)
                for (uint32_t x = t.x; x < t.x + t.width; ++x) covered[y * width + x] += 1;
        }
        for (int c : covered) ASSERT_EQ(c, 1) << "tile size " << tile_size;
    }
    EXPECT_NE(prism::test::error_message([] { prism::split_into_tiles(8, 8, 0); }).find("tile size 0"),
              std::string::npos);
}

TEST(Tiles, RegionOutsideTheImageIsRejected) {
    prism::RenderSettings settings = prism::test::small_settings(32, 16);
    settings.region = prism::PixelRect{24, 0, 16, 8};
    EXPECT_NE(prism::test::error_message([&] { prism::check_render_settings(settings); }).find("not inside"),
              std::string::npos);
}

// Every backend here: the tiles of a frame, rendered apart and put together, give the whole frame's bits (image and
// radiance). Uneven tiles (not dividing the image) check the kernels' pixel addressing at the edges.
class TileAgreement : public ::testing::TestWithParam<std::string> {};

TEST_P(TileAgreement, AssembledTilesEqualTheWholeFrame) {
    std::string backend = GetParam();
    std::string reason;
    if (!prism::test::backend_spec_runs_here(backend, &reason)) GTEST_SKIP() << reason;
    prism::LoadOptions load;
    load.data_dir = prism::test::scenes_dir().string();
    prism::Scene scene = prism::load_scene("builtin:sphere", load);
    prism::BvhBuildOptions bvh;
    bvh.layout = prism::resolve_bvh_layout("auto", backend);
    prism::DeviceScene device = prism::build_device_scene(scene, bvh);
    prism::RenderEngine engine(backend, device);
    prism::RenderSettings settings = prism::test::small_settings(53, 37, 4);
    settings.read_radiance = true;
    prism::FrameResult whole = engine.render(scene.camera, settings);

    std::vector<uint32_t> image(whole.image.size(), 0u);
    std::vector<float> radiance(whole.radiance.size(), -1.0f);
    uint64_t rays = 0;
    for (const prism::PixelRect& tile : prism::split_into_tiles(settings.width, settings.height, 20)) {
        prism::RenderSettings part = settings;
        part.region = tile;
        prism::FrameResult piece = engine.render(scene.camera, part);
        ASSERT_EQ(piece.width, tile.width);
        ASSERT_EQ(piece.image.size(), tile.pixels());
        prism::place_region(std::span<uint32_t>(image), settings.width, tile, std::span<const uint32_t>(piece.image));
        prism::place_region(std::span<float>(radiance), settings.width, tile, std::span<const float>(piece.radiance),
                            4);
        rays += piece.stats.total_rays();
    }
    EXPECT_EQ(image, whole.image);
    EXPECT_EQ(radiance, whole.radiance);
    EXPECT_EQ(rays, whole.stats.total_rays());
}

INSTANTIATE_TEST_SUITE_P(Backends, TileAgreement,
                         ::testing::Values("cpu-ref", "cpu", "cuda", prism::test::test_device("opencl"),
                                           prism::test::test_device("vulkan")),
                         [](const auto& info) { return prism::test::test_name_of(info.param); });

}  // namespace
