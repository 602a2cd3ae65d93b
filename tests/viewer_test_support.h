// Helpers of the viewer tests (test_viewer*.cpp): running `prism view` under Xvfb (or --headless) on the 320x180
// sphere, and comparing its window read-back with `prism render`.
#pragma once

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb_image.h>

#include "core/render/backend.h"
#include "tests/test_support.h"

namespace prism::test {

inline bool have_xvfb_run() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

#define REQUIRE_XVFB()                                                                                               \
    do {                                                                                                             \
        if (!prism::test::have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb xauth)"; \
    } while (0)

// Whether the backend runs here on a device whose name contains `device` (empty: any device).
inline bool backend_device_available(const std::string& api, const std::string& device, std::string* reason) {
    if (!backend_available(api, reason)) return false;
    if (device.empty()) return true;
    for (const prism::BackendFactory& f : prism::registered_backends()) {
        if (f.name != api) continue;
        for (std::string name : f.probe().devices) {
            for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
            if (name.find(device) != std::string::npos) return true;
        }
    }
    *reason = api + " runs here, but no device matches '" + device + "'";
    return false;
}

#define REQUIRE_BACKEND(api, device)                                                 \
    do {                                                                             \
        std::string reason;                                                          \
        if (!prism::test::backend_device_available(api, device, &reason))            \
            GTEST_SKIP() << api << " on '" << device << "' unavailable: " << reason; \
    } while (0)

// Skips a Vulkan-GL test whose `prism view` run (`result`) found this Mesa unable to share lavapipe memory with
// llvmpipe's GL; any other failure stays a failure.
#define SKIP_IF_MESA_CANNOT_SHARE(result)                                                                    \
    do {                                                                                                     \
        for (const char* missing : {"has no GL_EXT_memory_object_fd", "has no VK_KHR_external_memory_fd",    \
                                    "runs on another device or driver"})                                     \
            if ((result).exit_code == 1 && (result).output.find(missing) != std::string::npos)               \
                GTEST_SKIP() << "this Mesa cannot share lavapipe memory with llvmpipe: " << (result).output; \
    } while (0)

// A --stats file (null when missing or not JSON).
inline nlohmann::json read_json(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) return {};
    return nlohmann::json::parse(in, nullptr, false);
}

inline std::vector<uint32_t> read_png(const std::filesystem::path& path, int* width, int* height) {
    int channels = 0;
    unsigned char* pixels = stbi_load(path.c_str(), width, height, &channels, 4);
    if (!pixels) return {};
    std::vector<uint32_t> packed(size_t(*width) * size_t(*height));
    for (size_t i = 0; i < packed.size(); ++i)
        packed[i] = uint32_t(pixels[4 * i]) | uint32_t(pixels[4 * i + 1]) << 8 | uint32_t(pixels[4 * i + 2]) << 16 |
                    uint32_t(pixels[4 * i + 3]) << 24;
    stbi_image_free(pixels);
    return packed;
}

inline const std::string kScene = "--scene builtin:sphere --width 320 --height 180";

// Without the panel: these runs compare the window's pixels with `prism render` (test_viewer_live.cpp tests the
// panel itself).
inline CommandResult view(const std::string& arguments) {
    return run_prism("view " + kScene + " --no-panel " + arguments, "xvfb-run -a");
}

// PSNR of a viewer screenshot against `prism render` of the same scene, size and camera on `render_backend`.
inline double psnr_against_render(const std::filesystem::path& screenshot, const std::string& render_backend) {
    std::filesystem::path rendered = screenshot.parent_path() / ("render-" + screenshot.filename().string());
    CommandResult render =
        run_prism("render " + kScene + " --backend " + render_backend + " --out '" + rendered.string() + "'");
    EXPECT_EQ(render.exit_code, 0) << render.output;
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    std::vector<uint32_t> shown = read_png(screenshot, &w1, &h1);
    std::vector<uint32_t> expected = read_png(rendered, &w2, &h2);
    EXPECT_EQ(w1, 320);
    EXPECT_EQ(h1, 180);
    EXPECT_EQ(w1, w2);
    EXPECT_EQ(h1, h2);
    return psnr_rgba8(shown, expected);
}

}  // namespace prism::test
