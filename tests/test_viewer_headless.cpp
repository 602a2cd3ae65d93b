// `prism view --headless` (viewer/offscreen_window.h): an offscreen framebuffer in an EGL context, with no X server
// at all (DISPLAY unset) — how the viewer runs on GPU servers. Here EGL is Mesa's (llvmpipe): the read-back must
// equal `prism render`, through the host copy (cpu) and through the Vulkan-GL path (lavapipe), like the window.
#ifdef PRISM_HAVE_VIEWER

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/gltf_builder.h"
#include "tests/test_support.h"
#include "tests/viewer_test_support.h"

namespace {

using prism::test::kScene;
using prism::test::psnr_against_render;
using prism::test::read_json;

prism::test::CommandResult headless(const std::string& arguments) {
    return prism::test::run_prism("view " + kScene + " --headless --no-panel " + arguments,
                                  "env -u DISPLAY -u WAYLAND_DISPLAY");
}

TEST(ViewerHeadless, RendersOffscreenWithoutADisplay) {
    auto dir = prism::test::temp_dir("viewer-headless-cpu");
    std::filesystem::path shot = dir / "cpu.png", stats = dir / "stats.json";
    prism::test::CommandResult result =
        headless("--backend cpu --frames 3 --screenshot '" + shot.string() + "' --stats '" + stats.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("  offscreen 320x180, OpenGL "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(" via EGL device "), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("interop: host copy (the frame is already in host memory)"), std::string::npos)
        << result.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json["headless"], true);
    EXPECT_EQ(json["frames"], 3);
    EXPECT_EQ(json["display"]["path"], "host-copy");
    EXPECT_NE(json["gl"].get<std::string>().find(" via EGL "), std::string::npos) << json["gl"];
    // What the offscreen framebuffer holds is the frame `prism render` writes.
    EXPECT_GE(psnr_against_render(shot, "cpu"), 45.0);
}

TEST(ViewerHeadless, LavapipeSharesItsFrameWithEglGl) {
    REQUIRE_BACKEND("vulkan", "llvmpipe");
    auto dir = prism::test::temp_dir("viewer-headless-vulkan");
    std::filesystem::path shot = dir / "vulkan-gl.png", stats = dir / "stats.json";
    prism::test::CommandResult result =
        headless("--backend vulkan:llvmpipe --frames 3 --display interop --screenshot '" + shot.string() +
                 "' --stats '" + stats.string() + "'");
    SKIP_IF_MESA_CANNOT_SHARE(result);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json["display"]["path"], "interop");
    EXPECT_EQ(json["display"]["name"], "Vulkan-GL");
    EXPECT_GE(psnr_against_render(shot, "vulkan:llvmpipe"), 45.0);
}

// On a CUDA machine whose EGL is NVIDIA's (the H100): CUDA-GL both ways — memory CUDA exports and GL imports (the
// default), and the GL buffer registered with CUDA (PRISM_CUDA_GL=register) — shows what `prism render` writes.
TEST(ViewerHeadless, CudaGlShowsTheRenderedFrameBothWays) {
    REQUIRE_BACKEND("cuda", "");
    auto dir = prism::test::temp_dir("viewer-headless-cuda");
    for (std::string way : {"external", "register"}) {
        std::filesystem::path shot = dir / ("cuda-" + way + ".png"), stats = dir / ("stats-" + way + ".json");
        prism::test::CommandResult result = prism::test::run_prism(
            "view " + kScene + " --headless --no-panel --backend cuda --frames 3 --display interop --screenshot '" +
                shot.string() + "' --stats '" + stats.string() + "'",
            "env -u DISPLAY -u WAYLAND_DISPLAY" + std::string(way == "register" ? " PRISM_CUDA_GL=register" : ""));
        ASSERT_EQ(result.exit_code, 0) << result.output;
        nlohmann::json json = read_json(stats);
        EXPECT_EQ(json["display"]["name"], "CUDA-GL") << way;
        std::string detail = json["display"]["detail"];
        EXPECT_NE(detail.find(way == "register" ? "registered GL buffer" : "external memory"), std::string::npos)
            << detail;
        EXPECT_GE(psnr_against_render(shot, "cuda"), 45.0) << way;
    }
}

TEST(ViewerHeadless, ScriptedKeysStillApply) {
    // No window means no keyboard: --keys is the only input, and it must work (the moving object here).
    auto dir = prism::test::temp_dir("viewer-headless-keys");
    std::filesystem::path still = dir / "still.png", moved = dir / "moved.png";
    ASSERT_EQ(headless("--backend cpu --frames 3 --screenshot '" + still.string() + "'").exit_code, 0);
    prism::test::CommandResult result =
        headless("--backend cpu --frames 3 --keys 0:M --screenshot '" + moved.string() + "'");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    auto a = prism::test::read_png(still, &w1, &h1);
    auto b = prism::test::read_png(moved, &w2, &h2);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_LT(prism::test::psnr_rgba8(a, b), 40.0);  // the object moved
}

// M plays a glTF file's animation; headless, each frame advances it by MovingObject::kScriptedStep (1/30 s), so the
// 15th frame shows what `prism render --frames 15 --fps 30` shows: the animation half a second in. Full resolution
// while it moves (--interactive-scale 1): a slow build (sanitizers) would otherwise render the moving frames smaller.
// M played for `frames` headless frames (1/30 s each) shows what `prism render` shows at that time, and not the
// still frame.
void expect_m_plays(const std::filesystem::path& file, const std::string& status, int frames) {
    auto dir = prism::test::temp_dir("viewer-headless-animation-" + file.stem().string());
    const std::string scene = "--scene '" + file.string() + "' --allow-any-path --width 320 --height 180 ";
    const std::filesystem::path played = dir / "played.png", still = dir / "still.png";
    const std::string n = std::to_string(frames);
    prism::test::CommandResult view =
        prism::test::run_prism("view " + scene + "--headless --no-panel --backend cpu --frames " + n +
                                   " --keys 0:M --interactive-scale 1 --screenshot '" + played.string() + "'",
                               "env -u DISPLAY -u WAYLAND_DISPLAY");
    ASSERT_EQ(view.exit_code, 0) << view.output;
    EXPECT_NE(view.output.find(status), std::string::npos) << view.output;
    ASSERT_EQ(prism::test::run_prism("render " + scene + "--backend cpu --frames " + n + " --fps 30 --out '" +
                                     (dir / "render_%d.png").string() + "'")
                  .exit_code,
              0);
    ASSERT_EQ(prism::test::run_prism("render " + scene + "--backend cpu --out '" + still.string() + "'").exit_code, 0);
    int w = 0, h = 0;
    auto shown = prism::test::read_png(played, &w, &h);
    auto rendered = prism::test::read_png(dir / ("render_" + n + ".png"), &w, &h);
    auto at_rest = prism::test::read_png(still, &w, &h);
    ASSERT_EQ(shown.size(), rendered.size());
    EXPECT_GE(prism::test::psnr_rgba8(shown, rendered), 45.0);
    // It did move: counted in pixels, which a background's contrast does not change as it does a PSNR (with the
    // constant sky of a machine without the shared cube maps, 31.7 dB against the still frame).
    size_t moved = 0;
    for (size_t i = 0; i < shown.size() && i < at_rest.size(); ++i) moved += shown[i] != at_rest[i];
    EXPECT_GT(moved, shown.size() / 100);
}

TEST(ViewerHeadless, MPlaysTheScenesAnimation) {
    prism::test::GltfBuilder gltf;
    const int positions = gltf.positions({-1, -1, 0, 1, -1, 0, 0, 1, 0});
    const int mesh = gltf.mesh({{{"attributes", {{"POSITION", positions}}}}});
    gltf.node({{"mesh", mesh}, {"name", "triangle"}});
    const int times = gltf.view(std::vector<float>{0, 1});
    const int input = gltf.accessor({{"bufferView", times}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    const int keys = gltf.view(std::vector<float>{0, 0, 0, 0.6f, 0.3f, 0});
    const int output = gltf.accessor({{"bufferView", keys}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    gltf.document["animations"] = {
        {{"name", "slide"},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
         {"samplers", {{{"input", input}, {"output", output}}}}}};
    expect_m_plays(gltf.write("viewer-animated.gltf"), "  animation 'slide': playing\n", 15);
}

// A skin whose joints the animation turns (Khronos' SimpleSkin): the viewer poses the mesh anew every frame.
TEST(ViewerHeadless, MPlaysASkinnedMesh) {
    expect_m_plays(prism::test::scene("gltf/SimpleSkin/SimpleSkin.gltf"), "  animation 'animation 0': playing\n", 30);
}

// ] twice and T (a stop brighter, tone-mapped) show what --exposure 1 --tone-map neutral shows from the start.
TEST(ViewerHeadless, ExposureKeysMatchTheOptions) {
    auto dir = prism::test::temp_dir("viewer-headless-exposure");
    std::filesystem::path plain = dir / "plain.png", keys = dir / "keys.png", options = dir / "options.png";
    ASSERT_EQ(headless("--backend cpu --frames 2 --screenshot '" + plain.string() + "'").exit_code, 0);
    prism::test::CommandResult by_keys =
        headless("--backend cpu --frames 2 --keys 0:],0:],0:T --screenshot '" + keys.string() + "'");
    ASSERT_EQ(by_keys.exit_code, 0) << by_keys.output;
    EXPECT_NE(by_keys.output.find("  exposure +1.0 EV\n"), std::string::npos) << by_keys.output;
    EXPECT_NE(by_keys.output.find("  tone map neutral\n"), std::string::npos) << by_keys.output;
    ASSERT_EQ(
        headless("--backend cpu --frames 2 --exposure 1 --tone-map neutral --screenshot '" + options.string() + "'")
            .exit_code,
        0);
    int w = 0, h = 0;
    auto a = prism::test::read_png(plain, &w, &h), b = prism::test::read_png(keys, &w, &h),
         c = prism::test::read_png(options, &w, &h);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(b, c);
    EXPECT_LT(prism::test::psnr_rgba8(a, b), 30.0);  // visibly brighter
}

// PRISM_VIEW_ABLATE (bench/view_gpu.sh's split of the interop cost) is refused in one line where it cannot apply.
TEST(ViewerHeadless, AblationNeedsAnInteropWithoutSemaphores) {
    prism::test::CommandResult host = prism::test::run_prism("view " + kScene + " --headless --backend cpu --frames 1",
                                                             "env -u DISPLAY PRISM_VIEW_ABLATE=gl");
    EXPECT_EQ(host.exit_code, 1) << host.output;
    EXPECT_NE(host.output.find("prism: error: view: PRISM_VIEW_ABLATE needs an interop display without shared "
                               "semaphores (this one: interop: host copy (the frame is already in host memory))\n"),
              std::string::npos)
        << host.output;
    prism::test::CommandResult bad = prism::test::run_prism("view " + kScene + " --headless --backend cpu --frames 1",
                                                            "env -u DISPLAY PRISM_VIEW_ABLATE=draw");
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find("PRISM_VIEW_ABLATE='draw' is not one of copy, gl"), std::string::npos) << bad.output;
}

TEST(ViewerHeadless, NeedsAnEnd) {
    prism::test::CommandResult result = headless("--backend cpu");
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_EQ(result.output,
              "prism: error: view: --headless needs --frames or --seconds (there is no window to close)\n");
}

}  // namespace

#endif  // PRISM_HAVE_VIEWER
