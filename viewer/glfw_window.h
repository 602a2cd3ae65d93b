// The GLFW window (X11 or Wayland) and its OpenGL core context, with mouse and keyboard input, file drops and
// resizing; its callbacks also feed Dear ImGui's GLFW backend when the panel is up (viewer/panel.h).
#pragma once

#include <string>

#include "core/util/non_copyable.h"
#include "viewer/window.h"

struct GLFWwindow;

namespace prism::viewer {

class GlfwWindow final : public Window, private NonCopyable {
public:
    // Throws prism::Error "view: cannot open a window (...)" when there is no display or no GL 3.3 context.
    GlfwWindow(const std::string& title, int width, int height, bool vsync);
    ~GlfwWindow() override;

    bool should_close() const override;
    Input poll() override;
    Input wait(double timeout_seconds) override;
    void* glfw_window() const override;
    void set_title(const std::string& title) override;
    void swap() override;
    int framebuffer_width() const override;
    int framebuffer_height() const override;

private:
    uint32_t draw_framebuffer() const override { return 0; }
    void native_handles(GlContextHandles& gl) const override;

    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void on_cursor(GLFWwindow* window, double x, double y);
    static void on_mouse_button(GLFWwindow* window, int button, int action, int mods);
    static void on_scroll(GLFWwindow* window, double x, double y);
    static void on_drop(GLFWwindow* window, int count, const char** paths);
    static void on_framebuffer_size(GLFWwindow* window, int width, int height);
    static void on_char(GLFWwindow* window, unsigned int codepoint);
    static void on_focus(GLFWwindow* window, int focused);
    static void on_cursor_enter(GLFWwindow* window, int entered);
    Input take_pending();

    GLFWwindow* window_ = nullptr;
    enum class Drag { None, Orbit, Pan };
    Drag drag_ = Drag::None;
    glm::dvec2 last_cursor_{0.0};
};

}  // namespace prism::viewer
