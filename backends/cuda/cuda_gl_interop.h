// The CUDA-GL display path, two ways: memory CUDA allocates and exports (cuMemCreate + a POSIX fd) that GL imports
// as the buffer it draws from (GL_EXT_memory_object_fd), written by a device-to-device copy of the frame on the
// backend's stream; or, where GL cannot import memory, the GL buffer registered with CUDA
// (cudaGraphicsGLRegisterBuffer) and mapped around that copy. Like cuda_device.h, no CUDA types
// here: the CUDA headers and kernels/ must not meet in one translation unit.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "backends/cuda/cuda_device.h"
#include "core/render/gl_interop.h"

namespace prism::cuda {

// "" when the current GL context runs on `context`'s device (cudaGLGetDevices), else why CUDA-GL cannot work
// with it: "GL runs on llvmpipe (LLVM 15.0.6, 256 bits), not on a CUDA device". Needs the GL context current.
std::string gl_context_check(const DeviceContext& context, const std::string& gl_renderer);

// `image` returns the device pointer of the backend's image array (it moves when the frame size changes). External
// memory where `gl` offers GL_EXT_memory_object_fd and the driver exports POSIX fds (PRISM_CUDA_GL=register
// forces the registered buffer).
std::unique_ptr<GlInterop> create_gl_interop(DeviceContext& context, std::function<const void*()> image,
                                             const GlContextHandles& gl);

}  // namespace prism::cuda
