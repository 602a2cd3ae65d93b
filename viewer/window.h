// Where `prism view` shows its frames: a GLFW window with its OpenGL core context (viewer/glfw_window.*), or an
// offscreen framebuffer in an EGL context (viewer/offscreen_window.*: `--headless`, for GPU servers without an X
// server, where NVIDIA's GL runs only through EGL). Both give the frame display the same GL 4.5 (else 3.3) core
// context and a framebuffer of the frame's size, and read back what was drawn (`--screenshot`).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/gl_interop.h"
#include "viewer/key_script.h"

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
    virtual ~Window() = default;

    virtual bool should_close() const = 0;
    virtual Input poll() = 0;
    virtual void set_title(const std::string& title) = 0;
    // Shows the frame drawn (a buffer swap; offscreen, a glFlush that submits the frame's GL commands).
    virtual void swap() = 0;

    virtual int framebuffer_width() const = 0;
    virtual int framebuffer_height() const = 0;
    // "OpenGL 4.5 (Core Profile) Mesa 22.3.6 on llvmpipe (LLVM 15.0.6, 256 bits)", offscreen with " via EGL ..."
    const std::string& context_description() const { return context_description_; }
    // The frame just drawn, as packed RGBA8 (r in the low byte), row 0 at the top, alpha forced opaque.
    std::vector<uint32_t> read_pixels() const;
    // What a backend needs to share buffers with this GL context: the GLX or EGL handles, GL_RENDERER, the
    // external-memory extensions and GL's device/driver UUIDs (core/gl_interop.h).
    GlContextHandles gl_context_handles() const;

protected:
    // Called by the implementations once their context is current; `via` names how it was made, if not a window.
    void describe_context(const std::string& via = "");

private:
    // The framebuffer the frame is drawn into and read back from (0: the window's own).
    virtual uint32_t draw_framebuffer() const = 0;
    virtual void native_handles(GlContextHandles& gl) const = 0;

    std::string context_description_;
};

// Throws prism::Error "view: cannot open a window (...)" (with headless: "view: cannot create an offscreen GL
// context (...)") when there is no display, no EGL device or no GL 3.3 core context.
std::unique_ptr<Window> open_window(const std::string& title, int width, int height, bool vsync, bool headless);

}  // namespace prism::viewer
