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

#include "core/render/gl_interop.h"
#include "viewer/held_keys.h"
#include "viewer/key_script.h"

namespace prism::viewer {

// A fly key going down or up, with the time the window saw it (seconds on the steady clock, see
// viewer/held_keys.h): held keys move the camera by how long they were really held.
struct FlyKeyEvent {
    FlyKey key;
    bool pressed;
    double time;
};

// Everything the user did since the last poll.
struct Input {
    std::vector<Action> actions;        // key presses, in order
    std::vector<FlyKeyEvent> fly_keys;  // W/A/S/D/Q/E going down and up, in order
    glm::vec2 drag{0.0f};               // pixels moved with the left button held (x right, y down): orbit
    glm::vec2 pan{0.0f};                // pixels moved with the middle button, or Shift and the left button
    float scroll = 0.0f;                // wheel notches, positive away from the user
    std::vector<std::string> dropped;   // paths dropped onto the window
    bool resized = false;               // the framebuffer changed size
    bool other = false;                 // any other event (the pointer moved over the panel, a click on it...):
                                        // the panel is drawn again, the scene is not rendered again
    bool any() const {
        return !actions.empty() || !fly_keys.empty() || drag != glm::vec2(0.0f) || pan != glm::vec2(0.0f) ||
               scroll != 0.0f || !dropped.empty() || resized || other;
    }
};

class Window {
public:
    virtual ~Window() = default;

    virtual bool should_close() const = 0;
    // What happened since the last call, without waiting.
    virtual Input poll() = 0;
    // Waits for the next event (at most `timeout_seconds`), then returns what happened, like poll(): the idle
    // viewer sleeps here instead of rendering frames nobody asked for. Offscreen: sleeps the timeout.
    virtual Input wait(double timeout_seconds) = 0;
    // Paths dropped onto the window, as the drop callback hands them over (also `--drop`, scripted).
    void receive_drop(const std::vector<std::string>& paths);
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
    // external-memory extensions and GL's device/driver UUIDs (core/render/gl_interop.h).
    GlContextHandles gl_context_handles() const;

    // The GLFWwindow for Dear ImGui's GLFW backend (viewer/panel.h); null offscreen.
    virtual void* glfw_window() const { return nullptr; }

protected:
    // Called by the implementations once their context is current; `via` names how it was made, if not a window.
    void describe_context(const std::string& via = "");

private:
    // The framebuffer the frame is drawn into and read back from (0: the window's own).
    virtual uint32_t draw_framebuffer() const = 0;
    virtual void native_handles(GlContextHandles& gl) const = 0;

    std::string context_description_;

protected:
    Input pending_;  // what the callbacks collected since the last poll
};

// Now on the clock held keys are timed with (seconds since an arbitrary start, steady).
double input_clock();

// Throws prism::Error "view: cannot open a window (...)" (with headless: "view: cannot create an offscreen GL
// context (...)") when there is no display, no EGL device or no GL 3.3 core context.
std::unique_ptr<Window> open_window(const std::string& title, int width, int height, bool vsync, bool headless);

}  // namespace prism::viewer
