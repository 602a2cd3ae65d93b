// How a rendered frame reaches the window. One implementation per display path:
//   host copy  - glTexSubImage2D from FrameResult.image (every backend; what is implemented now);
//   interop    - CUDA-GL (cudaGraphicsGLRegisterBuffer), OpenCL cl_khr_gl_sharing, Vulkan external memory
//                (GL_EXT_memory_object_fd): the backend's display buffer shared with a GL texture, no host trip.
// choose_display_path() says which path a backend gets and why; create_frame_display() builds it. An interop
// path is one more FrameDisplay subclass plus a line in choose_display_path().
#pragma once

#include <memory>
#include <string>

#include "core/backend.h"
#include "core/renderer.h"

namespace prism::viewer {

struct DisplayPath {
    std::string name;     // "host copy"
    std::string reason;   // why this path: "PoCL has no GL sharing", ...
    // "interop: host copy (PoCL has no GL sharing)": what the HUD and the console show.
    std::string describe() const { return "interop: " + name + " (" + reason + ")"; }
};

DisplayPath choose_display_path(const BackendInfo& backend);

class FrameDisplay {
public:
    virtual ~FrameDisplay() = default;
    virtual const DisplayPath& path() const = 0;
    // Makes `frame` the displayed image (the GL context must be current).
    virtual void update(const FrameResult& frame) = 0;
    // Draws the displayed image over the whole viewport of the bound framebuffer.
    virtual void draw(int viewport_width, int viewport_height) = 0;
};

// Needs a current GL 3.3+ core context. Throws prism::Error when a shader fails to build.
std::unique_ptr<FrameDisplay> create_frame_display(const BackendInfo& backend);

}  // namespace prism::viewer
