// Buffer interop between a backend and the viewer's OpenGL context (docs/viewer.md, "Display paths"): the frame's
// RGBA8 image goes from the backend's `image` array into a GL buffer on the device, with no trip through host
// memory, and GL draws it from there. Handles travel as plain integers: core and the backends include no GL or X11
// header, and the viewer no GPU API header. The GPU API side of each path lives in backends/<api>/<api>_gl_interop.*,
// the GL side in viewer/.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace prism {

// The viewer's GL context, given to a backend at creation when the viewer wants frames to stay on the device
// (RenderEngine, create_backend). Each API uses what it needs and says why when something is missing.
struct GlContextHandles {
    uintptr_t x11_display = 0;      // Display* of the window (OpenCL: CL_GLX_DISPLAY_KHR); 0 when not X11
    uintptr_t glx_context = 0;      // GLXContext (OpenCL: CL_GL_CONTEXT_KHR); 0 when not GLX
    uintptr_t egl_display = 0;      // EGLDisplay of an offscreen context (OpenCL: CL_EGL_DISPLAY_KHR); 0 when not EGL
    uintptr_t egl_context = 0;      // EGLContext (OpenCL: CL_GL_CONTEXT_KHR); 0 when not EGL
    std::string renderer;           // GL_RENDERER, for messages
    bool memory_object_fd = false;  // GL_EXT_memory_object_fd: GL can use an exported opaque fd as buffer memory
    bool semaphore_fd = false;      // GL_EXT_semaphore_fd: GL can wait on and signal exported semaphores
    // GL_EXT_memory_object's GL_DEVICE_UUID_EXT (the first device) and GL_DRIVER_UUID_EXT; zero when unknown.
    // Memory exported by Vulkan is only valid in GL on the same device and driver.
    std::array<uint8_t, 16> device_uuid{};
    std::array<uint8_t, 16> driver_uuid{};
};

// Memory the device allocated and exported for GL to import (Vulkan-GL, CUDA-GL through external memory). GL takes
// ownership of the fds.
struct ExportedBuffer {
    int memory_fd = -1;
    uint64_t allocation_size = 0;    // of the whole allocation, as glImportMemoryFdEXT wants it
    bool dedicated = true;           // a dedicated allocation (GL_DEDICATED_MEMORY_OBJECT_EXT must match)
    int ready_semaphore_fd = -1;     // the frame's submission signals it after its copy; GL waits on it before
                                     // drawing (-1: no semaphores)
    int released_semaphore_fd = -1;  // GL signals it after reading the buffer; the next frame's submission waits on
                                     // it before its copy (-1: no semaphores)
};

// A backend's side of the shared display buffer. One buffer, written by copy_image() at the end of each shown
// frame, read by GL's draw in between.
class GlInterop {
public:
    virtual ~GlInterop() = default;
    // What the HUD names: "CUDA-GL", "OpenCL-GL", "Vulkan-GL".
    virtual std::string name() const = 0;
    // How the device and GL are ordered, e.g. "map/unmap on the CUDA stream", for the HUD and the stats.
    virtual std::string sync() const = 0;

    // Who allocates the buffer: GL (OpenCL, CUDA's registered buffer; the viewer creates a buffer object and calls
    // attach_gl_buffer) or the device (Vulkan, CUDA's external memory; the viewer calls export_buffer and imports
    // the result into GL).
    virtual bool device_owns_memory() const = 0;
    // Shares the GL buffer object `gl_buffer` of `bytes` with the device. Needs the GL context current. Throws
    // prism::Error with the API's cause when the driver refuses.
    virtual void attach_gl_buffer(uint32_t gl_buffer, size_t bytes);
    // Allocates `bytes` of exportable device memory (and the semaphores, where offered) and returns its fds.
    virtual ExportedBuffer export_buffer(size_t bytes);

    // Enqueues the device-to-device copy of the backend's `image` array into the shared buffer on the frame's
    // in-order queue, after the stages enqueued so far: Renderer calls it right after resolve when
    // RenderSettings::copy_to_gl is set, so the copy is part of the frame's own submission (no second submission,
    // no extra host wait) and the frame's completion completes it. When render() has returned GL may read the
    // buffer: the host has seen the frame finish (its counters read waits for the stream or queue), the registered
    // CUDA buffer's unmap has ordered GL after it, and with shared semaphores the copy's submission has also
    // signalled the ready semaphore GL waits on.
    virtual void copy_image(size_t bytes) = 0;
    // True when the API does not itself wait for GL to finish reading the buffer before the next frame's copy
    // writes it (CUDA with external memory, OpenCL, Vulkan without semaphores): copy_image() then first calls the
    // wait the viewer set (a GL fence). It runs where the host is idle anyway — the frame's stages are enqueued
    // and, on CUDA, already running — so GL's latency does not hold back the GPU.
    virtual bool needs_gl_idle_before_copy() const = 0;
    // The viewer's wait for GL to be done with the buffer (on the viewer's thread, its GL context current), or an
    // empty function to remove it.
    void set_gl_idle_wait(std::function<void()> wait) { gl_idle_wait_ = std::move(wait); }

protected:
    void wait_for_gl_idle() {
        if (gl_idle_wait_) gl_idle_wait_();
    }

private:
    std::function<void()> gl_idle_wait_;
};

// What a backend offers the viewer: an interop it owns, or why there is none ("PoCL has no cl_khr_gl_sharing").
struct GlInteropOffer {
    GlInterop* interop = nullptr;
    std::string reason;
};

}  // namespace prism
