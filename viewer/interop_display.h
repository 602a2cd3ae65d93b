// The interop display paths: a GL buffer shared with the backend (OpenCL-GL and CUDA's registered path: a GL buffer
// the device registers; Vulkan-GL and CUDA's external memory: device memory GL imports), the frame copied into it
// on the device by GlInterop::copy_image at the end of the frame's own submission (RenderSettings::copy_to_gl),
// then shown straight from it (a buffer texture or, --headless, a compute shader: GL copies nothing first).
// Synchronisation follows what the API offers (core/render/gl_interop.h): map/unmap for CUDA's registered buffer, the
// shared semaphores for Vulkan-GL where both sides offer them, otherwise a GL fence the host waits on right before
// the next frame's copy (GlInterop::set_gl_idle_wait).
#pragma once

#include <memory>

#include "viewer/frame_display.h"

namespace prism::viewer {

// Throws prism::Error when the buffer cannot be created, shared or imported.
std::unique_ptr<FrameDisplay> create_interop_display(DisplayPath path, GlInterop& interop, uint32_t width,
                                                     uint32_t height);

}  // namespace prism::viewer
