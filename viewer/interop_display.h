// The interop display paths: a GL buffer shared with the backend (CUDA-GL and OpenCL-GL: a GL buffer the device
// registers; Vulkan-GL: device memory GL imports), the frame copied into it on the device by
// GlInterop::copy_image, then drawn straight from it (a buffer texture: GL copies nothing). Synchronisation follows what the API offers
// (core/gl_interop.h): nothing to add for CUDA (map/unmap), a GL fence waited on before the next copy for OpenCL
// and for Vulkan without semaphores, the shared semaphores otherwise.
#pragma once

#include <memory>

#include "viewer/frame_display.h"

namespace prism::viewer {

// Throws prism::Error when the buffer cannot be created, shared or imported.
std::unique_ptr<FrameDisplay> create_interop_display(DisplayPath path, GlInterop& interop, uint32_t width,
                                                     uint32_t height);

}  // namespace prism::viewer
