// The GLFW window and its OpenGL core context (4.5, else 3.3), the input gathered each frame, and the read-back
// of the default framebuffer (what the user sees: `--screenshot` proves the display path with it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/gl_interop.h"
#include "viewer/key_script.h"

struct GLFWwindow;

namespace prism::viewer {

// Everything the user did since the last poll.
struct Input {
    std::vector<Action> actions;   // key presses, in order
    glm::vec2 drag{0.0f};          // pixels moved with the left button held (x right, y down)
    float scroll = 0.0f;           // wheel notches, positive away from the user
    glm::vec3 fly{0.0f};           // held WASD/QE: -1, 0 or 1 per camera axis (x right, y up, z forward)
};

class Window {
public:
    // Throws prism::Error "view: cannot open a window (...)" when there is no display or no GL 3.3 context.
    Window(const std::string& title, int width, int height, bool vsync);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    bool should_close() const;
    Input poll();
    void set_title(const std::string& title);
    void swap();
    // Waits until GL has executed everything issued (glFinish): lets --stats charge GL's work to the step that
    // issued it.
    void finish_gl();

    int framebuffer_width() const;
    int framebuffer_height() const;
    // "OpenGL 4.5 (Core Profile) Mesa 22.3.6 on llvmpipe (LLVM 15.0.6, 256 bits)"
    const std::string& context_description() const { return context_description_; }
    // The back buffer just drawn, as packed RGBA8 (r in the low byte), row 0 at the top, alpha forced opaque.
    std::vector<uint32_t> read_pixels() const;
    // What a backend needs to share buffers with this window's GL context: GLX handles, GL_RENDERER, the
    // external-memory extensions and GL's device/driver UUIDs (core/gl_interop.h).
    GlContextHandles gl_context_handles() const;

private:
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void on_cursor(GLFWwindow* window, double x, double y);
    static void on_mouse_button(GLFWwindow* window, int button, int action, int mods);
    static void on_scroll(GLFWwindow* window, double x, double y);

    GLFWwindow* window_ = nullptr;
    std::string context_description_;
    Input pending_;
    bool dragging_ = false;
    glm::dvec2 last_cursor_{0.0};
};

}  // namespace prism::viewer
