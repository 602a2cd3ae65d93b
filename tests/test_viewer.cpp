// `prism view`: the camera controls and --keys parsing as units, then the whole viewer under Xvfb — the window
// read-back must equal `prism render` of the same scene and camera (so the display path is proven, not just the
// renderer), backend switching, the moving object. GPU-API backends skip, with the reason, where absent.
#ifdef PRISM_HAVE_VIEWER

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "core/render/backend.h"
#include "core/util/error.h"
#include "tests/test_support.h"
#include "tests/viewer_test_support.h"
#include "viewer/camera_controls.h"
#include "viewer/frame_display.h"
#include "viewer/key_script.h"

namespace {

using prism::viewer::Action;

// --- units -------------------------------------------------------------------------------------------------

TEST(ViewerKeys, ParsesScriptSortedByFrame) {
    auto script = prism::viewer::parse_key_script("3:2,0:m,3:P,1:+,2:-,4:esc");
    ASSERT_EQ(script.size(), 6u);
    EXPECT_EQ(script[0].frame, 0u);
    EXPECT_EQ(script[0].action, Action::ToggleMoving);
    EXPECT_EQ(script[1].action, Action::DepthUp);
    EXPECT_EQ(script[2].action, Action::DepthDown);
    EXPECT_EQ(script[3].action, Action::Backend2);  // same frame: order kept
    EXPECT_EQ(script[4].action, Action::Screenshot);
    EXPECT_EQ(script[5].action, Action::Quit);
    EXPECT_TRUE(prism::viewer::parse_key_script("").empty());
    EXPECT_STREQ(prism::viewer::backend_for_key(Action::Backend1), "cpu-ref");
    EXPECT_STREQ(prism::viewer::backend_for_key(Action::Backend5), "vulkan");
    EXPECT_EQ(prism::viewer::backend_for_key(Action::Quit), nullptr);
}

TEST(ViewerKeys, RejectsBadScripts) {
    for (const char* bad : {"M", "x:M", "1:", ":M", "1:Z", "1:M,", "-1:M"}) {
        try {
            prism::viewer::parse_key_script(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const prism::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--keys: ", 0), 0u) << e.what();
        }
    }
}

prism::Camera test_camera() {
    prism::Camera camera;
    camera.position = {0.0f, 1.0f, 5.0f};
    camera.target = {0.0f, 1.0f, 0.0f};
    return camera;
}

TEST(ViewerCamera, OrbitKeepsDistanceAndTarget) {
    prism::viewer::CameraControls controls(test_camera());
    controls.orbit(glm::radians(90.0f), 0.0f);
    const prism::Camera& c = controls.camera();
    EXPECT_NEAR(glm::length(c.position - c.target), 5.0f, 1e-4f);
    EXPECT_NEAR(c.target.x, 0.0f, 1e-6f);
    EXPECT_NEAR(c.position.y, 1.0f, 1e-4f);  // a pure yaw stays at the same height
    EXPECT_NEAR(std::abs(c.position.x), 5.0f, 1e-4f);
    controls.orbit(0.0f, glm::radians(30.0f));  // the eye rises: 5 * sin(30°) above the target
    EXPECT_NEAR(glm::length(controls.camera().position - c.target), 5.0f, 1e-4f);
    EXPECT_NEAR(controls.camera().position.y, 1.0f + 2.5f, 1e-3f);
}

TEST(ViewerCamera, DraggingRightMovesTheEyeLeft) {
    prism::viewer::CameraControls controls(test_camera());  // eye on +z looking at -z: left is -x
    controls.orbit(0.1f, 0.0f);
    EXPECT_LT(controls.camera().position.x, 0.0f);
}

TEST(ViewerCamera, PitchStopsShortOfThePoles) {
    prism::viewer::CameraControls controls(test_camera());
    for (float pitch : {0.2f, -0.2f}) {
        for (int i = 0; i < 100; ++i) controls.orbit(0.0f, pitch);
        glm::vec3 direction = glm::normalize(controls.camera().position - controls.camera().target);
        EXPECT_NEAR(std::abs(glm::dot(direction, glm::vec3(0.0f, 1.0f, 0.0f))), std::cos(glm::radians(5.0f)), 1e-4f);
        EXPECT_GT(pitch * direction.y, 0.0f);  // stopped at the pole it was heading for
    }
}

TEST(ViewerCamera, FlyMovesEyeAndTargetTogetherAndZoomApproaches) {
    prism::viewer::CameraControls controls(test_camera());
    controls.fly({0.0f, 0.0f, 0.5f});  // forward: -z here, 0.5 world units
    EXPECT_NEAR(controls.camera().position.z, 4.5f, 1e-4f);
    EXPECT_NEAR(controls.camera().target.z, -0.5f, 1e-4f);
    controls.fly({1.0f, 0.0f, 0.0f});  // right: +x
    EXPECT_NEAR(controls.camera().position.x, 1.0f, 1e-4f);
    controls.zoom(1.0f);
    EXPECT_NEAR(glm::length(controls.camera().position - controls.camera().target), 4.5f, 1e-4f);
    for (int i = 0; i < 1000; ++i) controls.zoom(1.0f);  // never reaches the target
    EXPECT_GT(glm::length(controls.camera().position - controls.camera().target), 0.0f);
    controls.reset();
    EXPECT_EQ(controls.camera().position, test_camera().position);
}

// --- the viewer under Xvfb -----------------------------------------------------------------------------------

using prism::test::kScene;
using prism::test::psnr_against_render;
using prism::test::read_png;
using prism::test::view;

TEST(Viewer, WithoutDisplayFailsInOneLine) {
    prism::test::CommandResult result =
        prism::test::run_prism("view " + kScene + " --frames 1", "env -u DISPLAY -u WAYLAND_DISPLAY");
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_EQ(result.output, "prism: error: view: cannot open a window (no DISPLAY; run under xvfb-run -a)\n");
}

// Option errors come before any window: these run without xvfb-run (the GPU machine has none).
TEST(Viewer, ScreenshotNeedsFrames) {
    prism::test::CommandResult result = prism::test::run_prism("view " + prism::test::kScene + " --screenshot x.png");
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_NE(result.output.find("--screenshot needs --frames"), std::string::npos) << result.output;
}

// --seconds (bench/soak_viewer.sh's option) ends an unscripted session by itself and reports the frames it drew.
// No timing is asserted: only that it stops, cleanly, having rendered something.
TEST(Viewer, SecondsEndsTheSessionAndCountsFrames) {
    REQUIRE_XVFB();
    prism::test::CommandResult result = view("--backend cpu --seconds 0.5");
    EXPECT_EQ(result.exit_code, 0) << result.output;
    const size_t at = result.output.find("  rendered ");
    ASSERT_NE(at, std::string::npos) << result.output;
    EXPECT_GT(std::stoul(result.output.substr(at + 11)), 0u) << result.output;
    EXPECT_NE(result.output.find("last frame"), std::string::npos) << result.output;
}

TEST(Viewer, SecondsMustNotBeNegative) {
    prism::test::CommandResult result = prism::test::run_prism("view " + prism::test::kScene + " --seconds -1");
    EXPECT_NE(result.exit_code, 0) << result.output;
    EXPECT_LT(result.exit_code, 128) << result.output;
    EXPECT_NE(result.output.find("--seconds"), std::string::npos) << result.output;
}

struct ViewerBackend {
    std::string spec;  // as given to --backend
    std::string api;
    std::string device;  // substring of the device name that must be present, lower case
};

void PrintTo(const ViewerBackend& backend, std::ostream* out) { *out << backend.spec; }  // readable ctest names

class ViewerOnBackend : public testing::TestWithParam<ViewerBackend> {
protected:
    void SetUp() override {
        REQUIRE_XVFB();
        std::string reason;
        if (!prism::test::backend_device_available(GetParam().api, GetParam().device, &reason))
            GTEST_SKIP() << GetParam().spec << " unavailable: " << reason;
    }
};

TEST_P(ViewerOnBackend, WindowReadBackEqualsRender) {
    auto dir = prism::test::temp_dir("viewer-" + GetParam().api);
    std::filesystem::path shot = dir / "view.png";
    prism::test::CommandResult result =
        view("--backend " + GetParam().spec + " --frames 5 --screenshot '" + shot.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    // --display auto: PoCL and the cpu backend have no GL interop; lavapipe shares with llvmpipe where Mesa
    // offers it (test_viewer_interop.cpp checks which path and why).
    std::string path = GetParam().api == "vulkan" ? "interop: " : "interop: host copy (";
    EXPECT_NE(result.output.find(path), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("wrote " + shot.string() + " (window read-back, 320x180)"), std::string::npos)
        << result.output;
    EXPECT_GE(psnr_against_render(shot, GetParam().spec), 45.0);
}

TEST_P(ViewerOnBackend, MovingObjectChangesTheImage) {
    auto dir = prism::test::temp_dir("viewer-moving-" + GetParam().api);
    std::filesystem::path still = dir / "still.png", moving = dir / "moving.png";
    prism::test::CommandResult a =
        view("--backend " + GetParam().spec + " --frames 4 --screenshot '" + still.string() + "'");
    prism::test::CommandResult b =
        view("--backend " + GetParam().spec + " --frames 4 --keys 0:M --screenshot '" + moving.string() + "'");
    ASSERT_EQ(a.exit_code, 0) << a.output;
    ASSERT_EQ(b.exit_code, 0) << b.output;
    EXPECT_NE(b.output.find("moving object 'glass sphere': on"), std::string::npos) << b.output;
    int w = 0, h = 0;
    std::vector<uint32_t> still_pixels = read_png(still, &w, &h), moving_pixels = read_png(moving, &w, &h);
    ASSERT_EQ(still_pixels.size(), moving_pixels.size());
    EXPECT_LT(prism::test::psnr_rgba8(still_pixels, moving_pixels), 30.0);
}

INSTANTIATE_TEST_SUITE_P(Backends, ViewerOnBackend,
                         testing::Values(ViewerBackend{"cpu", "cpu", ""},
                                         ViewerBackend{"opencl:pocl", "opencl", "portable computing language"},
                                         ViewerBackend{"vulkan:llvmpipe", "vulkan", "llvmpipe"}),
                         [](const testing::TestParamInfo<ViewerBackend>& info) { return info.param.api; });

TEST(Viewer, SwitchesBackendLiveAndKeepsTheCamera) {
    REQUIRE_XVFB();
    auto dir = prism::test::temp_dir("viewer-switch");
    std::filesystem::path shot = dir / "switched.png";
    // cpu for frames 0-1, cpu-ref from frame 2: the last frame must be cpu-ref's image from the same camera.
    prism::test::CommandResult result =
        view("--backend cpu --frames 4 --keys 2:1 --screenshot '" + shot.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("switched to cpu-ref"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("last frame (cpu-ref ["), std::string::npos) << result.output;  // the final HUD line
    EXPECT_GE(psnr_against_render(shot, "cpu-ref"), 45.0);
}

TEST(Viewer, UnavailableBackendKeepsTheCurrentOne) {
    REQUIRE_XVFB();
    std::string unavailable;
    for (const char* api : {"cuda", "vulkan", "opencl"}) {
        if (!prism::test::backend_available(api)) {
            unavailable = api;
            break;
        }
    }
    if (unavailable.empty()) GTEST_SKIP() << "every backend runs here: none to fail switching to";
    const char* key = unavailable == "cuda" ? "3" : unavailable == "opencl" ? "4" : "5";
    auto dir = prism::test::temp_dir("viewer-unavailable");
    std::filesystem::path shot = dir / "kept.png";
    prism::test::CommandResult result =
        view("--backend cpu --frames 3 --keys 1:" + std::string(key) + " --screenshot '" + shot.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("backend " + unavailable + " unavailable ("), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("; keeping cpu"), std::string::npos) << result.output;
    // Asked before any work: no BVH built in the other backend's layout (cpu's is wide, the GPUs' stack).
    EXPECT_EQ(result.output.find("building the stack BVH"), std::string::npos) << result.output;
    EXPECT_GE(psnr_against_render(shot, "cpu"), 45.0);
}

TEST(Viewer, ScriptedCameraAndDepthKeysChangeTheFrame) {
    REQUIRE_XVFB();
    auto dir = prism::test::temp_dir("viewer-keys");
    std::filesystem::path moved = dir / "moved.png", reset = dir / "reset.png";
    prism::test::CommandResult a =
        view("--backend cpu --frames 2 --keys 0:W,0:D,0:- --screenshot '" + moved.string() + "'");
    prism::test::CommandResult b =
        view("--backend cpu --frames 2 --keys 0:W,0:+,1:R,1:- --screenshot '" + reset.string() + "'");
    ASSERT_EQ(a.exit_code, 0) << a.output;
    ASSERT_EQ(b.exit_code, 0) << b.output;
    EXPECT_NE(a.output.find("depth 7"), std::string::npos) << a.output;
    EXPECT_LT(psnr_against_render(moved, "cpu"), 30.0);  // the camera flew
    EXPECT_GE(psnr_against_render(reset, "cpu"), 45.0);  // R: back home, depth back to 8
}

}  // namespace

#endif  // PRISM_HAVE_VIEWER
