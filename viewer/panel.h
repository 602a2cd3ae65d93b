// The on-screen panel, drawn with Dear ImGui (Debian's libimgui-dev: its GLFW and OpenGL 3 backends) over the
// frame: what runs and how fast, the backend and depth as controls, messages (a file that failed to load), and
// the help overlay. Offscreen (--headless) it is drawn the same way, without input, so what it costs per frame
// can be measured where there is no window.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/util/non_copyable.h"
#include "viewer/window.h"

namespace prism::viewer {

// What the panel shows; the session fills it once per shown frame.
struct PanelView {
    std::string scene;
    std::string backend, device;
    std::string display_path;
    double fps = 0.0, frame_ms = 0.0;  // one smoothed wall-clock interval between shown frames, both from it
    double render_ms = 0.0;            // the last render, as RenderEngine measured it
    double mrays_per_second = 0.0;
    std::vector<std::pair<std::string, double>> stage_ms;
    uint32_t render_width = 0, render_height = 0;  // the last frame rendered (smaller while moving)
    uint32_t window_width = 0, window_height = 0;
    uint32_t depth = 0;
    float exposure = 0.0f;  // stops
    bool tone_map = false;  // Khronos PBR Neutral
    std::string activity;   // "idle", "moving (1/2 resolution)", "refining"
    uint64_t frames_rendered = 0, frames_shown = 0;
    std::string message;  // the last error or notice ("" none)
    bool message_is_error = false;
    std::vector<std::string> backends;  // the backend choices (key order)
};

// What the user changed through the panel this frame.
struct PanelRequest {
    std::optional<std::string> backend;
    std::optional<uint32_t> depth;
    std::optional<float> exposure;
    std::optional<bool> tone_map;
    bool reload = false;
    bool toggle_help = false;
};

class Panel : private NonCopyable {
public:
    // Needs the window's GL context current; throws prism::Error when Dear ImGui's GL backend cannot start.
    explicit Panel(Window& window);
    ~Panel();

    // Draws the panel (and the help overlay when `help`) over what the framebuffer holds.
    PanelRequest draw(const PanelView& view, bool help);
    // The pointer is over the panel: drags and scrolls there are the panel's, not the camera's.
    static bool wants_mouse();

private:
    PanelRequest build(const PanelView& view, bool help);  // one ImGui frame, up to ImGui::Render

    Window& window_;
    bool laid_out_ = false;
    bool glfw_ = false;
    double last_time_ = 0.0;
};

}  // namespace prism::viewer
