// The CUDA-GL display path: the GL buffer the viewer draws from, registered with CUDA (cudaGraphicsGLRegisterBuffer),
// mapped around a device-to-device copy of the frame on the backend's stream. Like cuda_device.h, no CUDA types
// here: the CUDA headers and kernels/ must not meet in one translation unit.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "backends/cuda/cuda_device.h"
#include "core/gl_interop.h"

namespace prism::cuda {

// "" when the current GL context runs on `context`'s device (cudaGLGetDevices), else why CUDA-GL cannot work
// with it: "GL runs on llvmpipe (LLVM 15.0.6, 256 bits), not on a CUDA device". Needs the GL context current.
std::string gl_context_check(const DeviceContext& context, const std::string& gl_renderer);

// `image` returns the device pointer of the backend's image array (it moves when the frame size changes).
std::unique_ptr<GlInterop> create_gl_interop(DeviceContext& context, std::function<const void*()> image);

}  // namespace prism::cuda
