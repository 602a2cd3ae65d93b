// `prism view --headless`: the frame display draws into a framebuffer object of the frame's size in an offscreen
// EGL context, created on an EGL device (EGL_EXT_platform_device) or Mesa's surfaceless platform. This is how
// NVIDIA's GL runs on a GPU server without an X server: its GLX client needs NVIDIA's own X server (it asks the
// server for NV-GLX and gives up without it, so Xvfb cannot serve it). Input comes only from --keys and --drop.
#pragma once

#include <cstdint>
#include <string>

#include "core/util/non_copyable.h"
#include "viewer/window.h"

namespace prism::viewer {

class OffscreenWindow final : public Window, private NonCopyable {
public:
    // Throws prism::Error "view: cannot create an offscreen GL context (...)".
    OffscreenWindow(int width, int height);
    ~OffscreenWindow() override;

    bool should_close() const override { return false; }
    Input poll() override;
    Input wait(double timeout_seconds) override;  // no events come: sleeps the timeout
    void set_title(const std::string&) override {}
    void swap() override;
    int framebuffer_width() const override { return width_; }
    int framebuffer_height() const override { return height_; }

private:
    uint32_t draw_framebuffer() const override { return framebuffer_; }
    void native_handles(GlContextHandles& gl) const override;
    void release();  // the framebuffer, the context and the display, once

    int width_, height_;
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
    uint32_t framebuffer_ = 0;
    uint32_t color_ = 0;    // the framebuffer's RGBA8 texture
    std::string platform_;  // "EGL device 0 (EGL_NV_device_cuda ...)", "Mesa surfaceless platform"
};

}  // namespace prism::viewer
