// `prism view` display paths (docs/viewer.md): which path --display gives and why (units), the timing summary, and
// under Xvfb: the fallback to the host copy where a backend cannot share with GL (cpu, PoCL), the Vulkan-GL path
// from lavapipe into llvmpipe's GL where Mesa offers it (the window read-back must equal `prism render`), forcing
// either path, --display none, and --stats.
#ifdef PRISM_HAVE_VIEWER

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "core/render/gl_interop.h"
#include "tests/test_support.h"
#include "tests/viewer_test_support.h"
#include "viewer/frame_display.h"
#include "viewer/frame_timing.h"

namespace {

using prism::test::psnr_against_render;
using prism::test::read_json;
using prism::test::view;
using prism::viewer::DisplayMode;
using prism::viewer::DisplayPath;

// --- units -------------------------------------------------------------------------------------------------

class FakeInterop final : public prism::GlInterop {
public:
    std::string name() const override { return "Fake-GL"; }
    std::string sync() const override { return "fake fence"; }
    bool device_owns_memory() const override { return false; }
    void copy_image(size_t) override {}
    bool needs_gl_idle_before_copy() const override { return false; }
};

const prism::BackendInfo kPocl{"opencl", "pthread-haswell-AMD EPYC", "", "", 0, 0};

TEST(ViewerDisplayPath, AutoTakesTheInteropTheBackendOffers) {
    FakeInterop interop;
    DisplayPath path = prism::viewer::choose_display_path(DisplayMode::Auto, kPocl, {&interop, ""});
    EXPECT_EQ(path.kind, DisplayPath::Kind::Interop);
    EXPECT_EQ(path.describe(), "interop: Fake-GL (sync: fake fence)");
    EXPECT_STREQ(path.kind_name(), "interop");
    prism::RenderSettings settings;
    prism::viewer::set_read_back(path, settings);
    EXPECT_FALSE(settings.read_image);  // the frame's own submission copies the device's image into GL's buffer
    EXPECT_TRUE(settings.copy_to_gl);
    EXPECT_FALSE(settings.read_radiance);
    prism::viewer::set_read_back(path, settings, false);  // a frame only rendered (--alternate-display)
    EXPECT_FALSE(settings.copy_to_gl);
    EXPECT_FALSE(settings.read_image);
}

TEST(ViewerDisplayPath, AutoFallsBackToHostCopyAndSaysWhy) {
    DisplayPath path = prism::viewer::choose_display_path(
        DisplayMode::Auto, kPocl, {nullptr, "Portable Computing Language has no cl_khr_gl_sharing"});
    EXPECT_EQ(path.describe(), "interop: host copy (Portable Computing Language has no cl_khr_gl_sharing)");
    EXPECT_STREQ(path.kind_name(), "host-copy");
    prism::RenderSettings settings;
    prism::viewer::set_read_back(path, settings);
    EXPECT_TRUE(settings.read_image);
    EXPECT_FALSE(settings.copy_to_gl);
    EXPECT_FALSE(settings.read_radiance);
    prism::viewer::set_read_back(path, settings, false);
    EXPECT_FALSE(settings.read_image);
}

TEST(ViewerDisplayPath, HostCopyAndNoneAreForcedEvenWithInterop) {
    FakeInterop interop;
    EXPECT_EQ(prism::viewer::choose_display_path(DisplayMode::HostCopy, kPocl, {&interop, ""}).describe(),
              "interop: host copy (--display host-copy)");
    DisplayPath none = prism::viewer::choose_display_path(DisplayMode::None, kPocl, {&interop, ""});
    EXPECT_EQ(none.kind, DisplayPath::Kind::None);
    prism::RenderSettings settings;
    prism::viewer::set_read_back(none, settings);
    EXPECT_FALSE(settings.read_image);  // render alone: nothing leaves the device
    EXPECT_FALSE(settings.copy_to_gl);
}

TEST(ViewerDisplayPath, ForcedInteropWithoutOneIsAnError) {
    std::string message = prism::test::error_message([] {
        prism::viewer::choose_display_path(DisplayMode::Interop, kPocl, {nullptr, "no cl_khr_gl_sharing"});
    });
    EXPECT_EQ(message,
              "view: --display interop: no GL interop for opencl [pthread-haswell-AMD EPYC] "
              "(no cl_khr_gl_sharing)");
}

TEST(ViewerDisplayPath, ParsesTheModes) {
    EXPECT_EQ(prism::viewer::parse_display_mode("auto"), DisplayMode::Auto);
    EXPECT_EQ(prism::viewer::parse_display_mode("interop"), DisplayMode::Interop);
    EXPECT_EQ(prism::viewer::parse_display_mode("host-copy"), DisplayMode::HostCopy);
    EXPECT_EQ(prism::viewer::parse_display_mode("none"), DisplayMode::None);
    EXPECT_EQ(prism::test::error_message([] { prism::viewer::parse_display_mode("hostcopy"); }),
              "view: --display 'hostcopy' is not one of auto, interop, host-copy, none");
}

TEST(ViewerFrameTimings, MediansSkipTheWarmUp) {
    prism::viewer::FrameTimings timings;
    // Warm-up frames are slow (first launches); they must not move the medians.
    for (int i = 0; i < 5; ++i) timings.add({1000.0, 100.0, 10.0, 1110.0});
    for (int i = 0; i < 15; ++i) timings.add({10.0 + i, 1.0, 0.5, 12.0 + i});
    EXPECT_EQ(timings.warmup(), 5u);
    prism::viewer::FrameTimings::Summary s = timings.summary();
    EXPECT_EQ(s.measured, 15u);
    EXPECT_DOUBLE_EQ(s.render_ms, 17.0);
    EXPECT_DOUBLE_EQ(s.display_ms, 1.0);
    EXPECT_DOUBLE_EQ(s.present_ms, 0.5);
    EXPECT_DOUBLE_EQ(s.frame_ms, 19.0);
    EXPECT_NEAR(s.fps, 1000.0 / 19.0, 1e-9);
    nlohmann::json json = timings.json();
    EXPECT_EQ(json["per_frame"]["frame_ms"].size(), 20u);
    EXPECT_EQ(json["warmup_frames"], 5);

    prism::viewer::FrameTimings two;  // short runs keep most frames: 1 of 4 is warm-up
    for (double ms : {50.0, 4.0, 6.0, 8.0}) two.add({ms, 0.0, 0.0, ms});
    EXPECT_EQ(two.warmup(), 1u);
    EXPECT_DOUBLE_EQ(two.summary().frame_ms, 6.0);
}

TEST(ViewerFrameTimings, AlternatingBlocksCompareShownWithHiddenFrames) {
    using Block = prism::viewer::FrameTiming::Block;
    prism::viewer::FrameTimings timings;
    // 24 frames in blocks of 3: shown frames take 10.3 ms, hidden ones 10.0 ms; the first of each block carries
    // the block before it (here 50 ms) and must be left out, as must the 5 warm-up frames.
    for (int i = 0; i < 24; ++i) {
        prism::viewer::FrameTiming t;
        t.block = (i / 3) % 2 ? Block::Hidden : Block::Shown;
        t.first_of_block = i % 3 == 0;
        t.render_ms = 10.0;
        t.frame_ms = t.first_of_block ? 50.0 : (t.block == Block::Shown ? 10.3 : 10.0);
        timings.add(t);
    }
    prism::viewer::FrameTimings::Summary s = timings.summary();
    EXPECT_EQ(s.shown, 6u);   // frames 7 8, 13 14, 19 20
    EXPECT_EQ(s.hidden, 7u);  // frames 5 (4 is warm-up), 10 11, 16 17, 22 23
    EXPECT_DOUBLE_EQ(s.shown_frame_ms, 10.3);
    EXPECT_DOUBLE_EQ(s.hidden_frame_ms, 10.0);
    EXPECT_NEAR(s.added_ms, 0.3, 1e-12);
    nlohmann::json json = timings.json();
    EXPECT_NEAR(double(json["alternating"]["added_ms"]), 0.3, 1e-12);
    EXPECT_EQ(json["per_frame"]["shown"][3], false);
    EXPECT_NE(timings.summary_line().find("showing adds 0.300 ms"), std::string::npos) << timings.summary_line();

    prism::viewer::FrameTimings plain;  // without --alternate-display there is no comparison
    for (int i = 0; i < 8; ++i) plain.add({10.0, 0.1, 0.1, 10.2});
    EXPECT_EQ(plain.summary().shown, 0u);
    EXPECT_TRUE(plain.json()["alternating"].is_null());
    EXPECT_EQ(plain.summary_line().find("alternating"), std::string::npos);
}

// --- under Xvfb ----------------------------------------------------------------------------------------------

TEST(ViewerInterop, CpuShowsItsHostFrameAndReportsTimings) {
    REQUIRE_XVFB();
    auto dir = prism::test::temp_dir("viewer-interop-cpu");
    std::filesystem::path stats = dir / "stats.json";
    prism::test::CommandResult result = view("--backend cpu --frames 4 --stats '" + stats.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("interop: host copy (the frame is already in host memory)"), std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find("timing: 3 frames after 1 warm-up, median render "), std::string::npos)
        << result.output;
    nlohmann::json json = read_json(stats);
    ASSERT_TRUE(json.is_object()) << stats;
    EXPECT_EQ(json["display"]["requested"], "auto");
    EXPECT_EQ(json["display"]["path"], "host-copy");
    EXPECT_EQ(json["display"]["detail"], "the frame is already in host memory");
    EXPECT_EQ(json["backend"]["name"], "cpu");
    EXPECT_EQ(json["frames"], 4);
    EXPECT_EQ(json["per_frame"]["render_ms"].size(), 4u);
    double render = json["median_render_ms"], display = json["median_display_ms"], frame = json["median_frame_ms"];
    EXPECT_GT(render, 0.0);
    EXPECT_GT(display, 0.0);
    EXPECT_GT(double(json["median_present_ms"]), 0.0);
    EXPECT_GE(frame, render);  // a frame holds its render and its display
    EXPECT_NEAR(double(json["fps"]), 1000.0 / frame, 1e-6);
    EXPECT_EQ(json["width"], 320);
}

TEST(ViewerInterop, PoclFallsBackToHostCopy) {
    REQUIRE_XVFB();
    REQUIRE_BACKEND("opencl", "portable computing language");
    auto dir = prism::test::temp_dir("viewer-interop-pocl");
    std::filesystem::path stats = dir / "stats.json", shot = dir / "pocl.png";
    prism::test::CommandResult result =
        view("--backend opencl:pocl --frames 2 --screenshot '" + shot.string() + "' --stats '" + stats.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("interop: host copy (Portable Computing Language has no cl_khr_gl_sharing)"),
              std::string::npos)
        << result.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json["display"]["path"], "host-copy");
    EXPECT_GE(psnr_against_render(shot, "opencl:pocl"), 45.0);
}

TEST(ViewerInterop, ForcedInteropWithoutItFailsInOneLine) {
    REQUIRE_XVFB();
    // --quiet keeps the loading steps' progress lines (docs/cli.md) out: the error must be all that is left.
    prism::test::CommandResult result = view("--backend cpu --frames 2 --display interop --quiet");
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_EQ(result.output.rfind("prism: error: view: --display interop: no GL interop for cpu [", 0), 0u)
        << result.output;
    EXPECT_NE(result.output.find("(the frame is already in host memory)\n"), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

TEST(ViewerInterop, BadDisplayModeAndScreenshotWithoutDisplayFailInOneLine) {
    prism::test::CommandResult bad = prism::test::run_prism("view " + prism::test::kScene + " --display hostcopy");
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find("--display 'hostcopy' is not one of auto, interop, host-copy, none"), std::string::npos)
        << bad.output;
    prism::test::CommandResult none =
        prism::test::run_prism("view " + prism::test::kScene + " --display none --frames 1 --screenshot x.png");
    EXPECT_EQ(none.exit_code, 1) << none.output;
    EXPECT_EQ(none.output, "prism: error: view: --screenshot needs a display (--display none shows nothing)\n");
}

TEST(ViewerInterop, DisplayNoneRendersWithoutShowing) {
    REQUIRE_XVFB();
    auto dir = prism::test::temp_dir("viewer-interop-none");
    std::filesystem::path stats = dir / "stats.json";
    prism::test::CommandResult result =
        view("--backend cpu --frames 3 --display none --stats '" + stats.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("display: none (--display none: frames are rendered, not shown)"), std::string::npos)
        << result.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json["display"]["path"], "none");
    EXPECT_GT(double(json["median_render_ms"]), 0.0);
    EXPECT_LT(double(json["median_display_ms"]), 1.0);  // no upload, no draw, no swap: nothing but a clock read
    EXPECT_LT(double(json["median_present_ms"]), 1.0);
}

// Mesa offers GL_EXT_memory_object_fd in llvmpipe's GL and VK_KHR_external_memory_fd in lavapipe, with the same
// device and driver UUIDs: the Vulkan-GL path runs for real here, with fence waits (no GL_EXT_semaphore_fd).
// Skips only when this Mesa lacks one of those (the reason says which); any other failure is a failure.
TEST(ViewerInterop, LavapipeSharesItsFrameWithLlvmpipe) {
    REQUIRE_XVFB();
    REQUIRE_BACKEND("vulkan", "llvmpipe");
    auto dir = prism::test::temp_dir("viewer-interop-vulkan");
    std::filesystem::path stats = dir / "stats.json", shot = dir / "vulkan-gl.png";
    prism::test::CommandResult result = view("--backend vulkan:llvmpipe --frames 3 --display interop --screenshot '" +
                                             shot.string() + "' --stats '" + stats.string() + "'");
    SKIP_IF_MESA_CANNOT_SHARE(result);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("interop: Vulkan-GL (sync: fence waits, no shared semaphores ("), std::string::npos)
        << result.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json["display"]["requested"], "interop");
    EXPECT_EQ(json["display"]["path"], "interop");
    EXPECT_EQ(json["display"]["name"], "Vulkan-GL");
    // The window shows what the device copied into GL's buffer: the frame `prism render` writes.
    EXPECT_GE(psnr_against_render(shot, "vulkan:llvmpipe"), 45.0);
}

// --alternate-display with the Vulkan-GL path: hidden frames skip the frame's copy into GL's buffer and the
// draw, the shown ones after them must still see the new frame (the semaphores/fences stay paired), and the last
// frame (in a hidden block here) is shown for the screenshot. Both runs fix --interactive-scale at 1: "auto" sizes
// a moving frame from the measured render times, so on a busy machine two runs would render the last frame at
// different resolutions.
TEST(ViewerInterop, AlternatingDisplayKeepsTheInteropInStep) {
    REQUIRE_XVFB();
    REQUIRE_BACKEND("vulkan", "llvmpipe");
    auto dir = prism::test::temp_dir("viewer-interop-alternate");
    std::filesystem::path stats = dir / "stats.json", shot = dir / "alternate.png";
    prism::test::CommandResult result = view(
        "--backend vulkan:llvmpipe --frames 7 --alternate-display 2 --keys 0:M --interactive-scale 1 "
        "--display interop --screenshot '" +
        shot.string() + "' --stats '" + stats.string() + "'");
    SKIP_IF_MESA_CANNOT_SHARE(result);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("; alternating: shown "), std::string::npos) << result.output;
    nlohmann::json json = read_json(stats);
    ASSERT_TRUE(json["alternating"].is_object()) << json.dump();
    EXPECT_GT(int(json["alternating"]["shown_frames"]), 0);
    EXPECT_GT(int(json["alternating"]["hidden_frames"]), 0);
    const nlohmann::json& shown = json["per_frame"]["shown"];
    ASSERT_EQ(shown.size(), 7u);
    EXPECT_EQ(shown[0], true);
    EXPECT_EQ(shown[2], false);
    EXPECT_EQ(shown[4], true);
    EXPECT_TRUE(shown[6].is_null());  // the last frame, shown for the screenshot, is in neither median
    // The screenshot is the last frame with the object moved 7 times: `prism render` cannot pose it, so compare
    // with the same run fully shown.
    std::filesystem::path every = dir / "every.png";
    prism::test::CommandResult reference = view(
        "--backend vulkan:llvmpipe --frames 7 --keys 0:M --interactive-scale 1 "
        "--display interop --screenshot '" +
        every.string() + "'");
    ASSERT_EQ(reference.exit_code, 0) << reference.output;
    int width = 0, height = 0, every_width = 0, every_height = 0;
    std::vector<uint32_t> alternated = prism::test::read_png(shot, &width, &height);
    std::vector<uint32_t> all_shown = prism::test::read_png(every, &every_width, &every_height);
    ASSERT_EQ(width, every_width);
    ASSERT_EQ(height, every_height);
    EXPECT_TRUE(alternated == all_shown) << "PSNR " << prism::test::psnr_rgba8(alternated, all_shown);
}

TEST(ViewerInterop, HostCopyCanBeForcedOnLavapipe) {
    REQUIRE_XVFB();
    REQUIRE_BACKEND("vulkan", "llvmpipe");
    auto dir = prism::test::temp_dir("viewer-interop-vulkan-host");
    std::filesystem::path shot = dir / "host.png";
    prism::test::CommandResult result =
        view("--backend vulkan:llvmpipe --frames 2 --display host-copy --screenshot '" + shot.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("interop: host copy (--display host-copy)"), std::string::npos) << result.output;
    EXPECT_GE(psnr_against_render(shot, "vulkan:llvmpipe"), 45.0);
}

}  // namespace

#endif  // PRISM_HAVE_VIEWER
