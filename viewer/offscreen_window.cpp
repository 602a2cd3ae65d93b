#include "viewer/offscreen_window.h"

#include <chrono>
#include <cstdio>
#include <thread>
#include <cstring>
#include <vector>

#define EGL_NO_X11  // no Xlib types in eglplatform.h: this context has no window system
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "core/util/error.h"
#include "viewer/gl.h"
#include "viewer/gl_external.h"

namespace prism::viewer {
namespace {

Error cannot_create(const std::string& why) {
    return Error("view: cannot create an offscreen GL context (" + why + ")");
}

std::string egl_error(const char* call) {
    char text[64];
    std::snprintf(text, sizeof text, "%s failed: EGL error 0x%04x", call, unsigned(eglGetError()));
    return text;
}

bool lists(const char* extensions, const char* name) {
    if (!extensions) return false;
    size_t length = std::strlen(name);
    for (const char* p = std::strstr(extensions, name); p; p = std::strstr(p + 1, name))
        if ((p == extensions || p[-1] == ' ') && (p[length] == ' ' || p[length] == '\0')) return true;
    return false;
}

GlFunction egl_proc_address(const char* name) { return reinterpret_cast<GlFunction>(eglGetProcAddress(name)); }

// A GL 4.5 core context (else 3.3) on `display`, current without a surface; nullptr (why in `why`) when not.
EGLContext create_context(EGLDisplay display, std::string* why) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        *why = egl_error("eglInitialize");
        return EGL_NO_CONTEXT;
    }
    if (!lists(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
        *why = "no EGL_KHR_surfaceless_context";
        eglTerminate(display);
        return EGL_NO_CONTEXT;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        *why = egl_error("eglBindAPI(EGL_OPENGL_API)");
        eglTerminate(display);
        return EGL_NO_CONTEXT;
    }
    // EGL_SURFACE_TYPE 0: no surface is ever made (the default, EGL_WINDOW_BIT, matches nothing offscreen).
    const EGLint config_attributes[] = {
        EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
        EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, config_attributes, &config, 1, &configs) || configs == 0) {
        *why = "no EGL config renders OpenGL";
        eglTerminate(display);
        return EGL_NO_CONTEXT;
    }
    for (EGLint version : {45, 33}) {
        const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                             version / 10,
                                             EGL_CONTEXT_MINOR_VERSION,
                                             version % 10,
                                             EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                             EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                             EGL_NONE};
        EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
        if (context == EGL_NO_CONTEXT) continue;
        if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) return context;
        eglDestroyContext(display, context);
    }
    *why = "no OpenGL 4.5 or 3.3 core context: " + egl_error("eglCreateContext");
    eglTerminate(display);
    return EGL_NO_CONTEXT;
}

}  // namespace

OffscreenWindow::OffscreenWindow(int width, int height) : width_(width), height_(height) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::string tried;
    // The GPU itself (EGL_EXT_platform_device): NVIDIA's EGL, and Mesa's devices. The first that gives a context.
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (lists(client, "EGL_EXT_platform_device") && query_devices) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (query_devices(16, devices, &count)) {
            for (EGLint i = 0; i < count && !context_; ++i) {
                EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                std::string why = "no display";
                EGLContext context = display != EGL_NO_DISPLAY ? create_context(display, &why) : EGL_NO_CONTEXT;
                const char* extensions = query_device_string ? query_device_string(devices[i], EGL_EXTENSIONS) : "";
                std::string name = "EGL device " + std::to_string(i) + " (" + (extensions ? extensions : "") + ")";
                if (context != EGL_NO_CONTEXT) {
                    display_ = display;
                    context_ = context;
                    platform_ = name;
                } else {
                    tried += (tried.empty() ? "" : "; ") + name + ": " + why;
                }
            }
        } else {
            tried = egl_error("eglQueryDevicesEXT");
        }
    }
    // Mesa without a device platform: its surfaceless platform renders on whatever Mesa's default driver is.
    if (!context_ && lists(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        std::string why = "no display";
        EGLContext context = display != EGL_NO_DISPLAY ? create_context(display, &why) : EGL_NO_CONTEXT;
        if (context != EGL_NO_CONTEXT) {
            display_ = display;
            context_ = context;
            platform_ = "Mesa surfaceless platform";
        } else {
            tried += std::string(tried.empty() ? "" : "; ") + "Mesa surfaceless platform: " + why;
        }
    }
    if (!context_)
        throw cannot_create(tried.empty() ? "EGL offers neither a device nor a surfaceless platform" : tried);
    set_gl_proc_address(egl_proc_address);
    describe_context(platform_);

    // The frame's framebuffer: one RGBA8 color texture of the frame's size, bound for drawing from now on (a texture,
    // not a renderbuffer: the interop display writes it with a compute shader, viewer/texture_quad.h).
    glGenTextures(1, &color_);
    glBindTexture(GL_TEXTURE_2D, color_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char text[96];
        std::snprintf(text, sizeof text, "a %dx%d RGBA8 framebuffer is incomplete (status 0x%04x)", width, height,
                      unsigned(status));
        release();
        throw cannot_create(text);
    }
}

OffscreenWindow::~OffscreenWindow() { release(); }

void OffscreenWindow::release() {
    if (!context_) return;
    if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
    if (color_) glDeleteTextures(1, &color_);
    framebuffer_ = color_ = 0;
    set_gl_proc_address(nullptr);
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
    context_ = nullptr;
}

// No buffer to present: submit the frame's GL commands, as a swap would, so they run while the next frame renders.
void OffscreenWindow::swap() { glFlush(); }

Input OffscreenWindow::poll() {
    Input input = std::move(pending_);
    pending_ = Input{};
    return input;
}

Input OffscreenWindow::wait(double timeout_seconds) {
    if (pending_.any()) return poll();
    if (timeout_seconds > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(timeout_seconds));
    return poll();
}

void OffscreenWindow::native_handles(GlContextHandles& gl) const {
    gl.egl_display = reinterpret_cast<uintptr_t>(display_);
    gl.egl_context = reinterpret_cast<uintptr_t>(context_);
}

}  // namespace prism::viewer
