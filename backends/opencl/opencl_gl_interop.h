// The OpenCL-GL display path (cl_khr_gl_sharing): an OpenCL context created together with the viewer's GLX or EGL
// context, the GL buffer the viewer draws from wrapped with clCreateFromGLBuffer, and per frame acquire, a
// device-to-device clEnqueueCopyBuffer of the image array, release, clFinish.
#pragma once

#include <CL/cl.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/render/gl_interop.h"

namespace prism::opencl_gl {

// The context properties that tie a new context on `device` to the viewer's GL context, ending with 0. Empty, with
// `reason` saying why, when the device cannot share with it: no cl_khr_gl_sharing (PoCL), neither GLX nor EGL, or
// GL running on another device.
struct ContextSharing {
    std::vector<cl_context_properties> properties;
    std::string reason;
};
ContextSharing context_properties(cl_platform_id platform, cl_device_id device, const std::string& platform_name,
                                  const std::string& device_name, const GlContextHandles& gl);

// `image` returns the backend's image buffer (it changes when the frame size does).
std::unique_ptr<GlInterop> create_gl_interop(cl_context context, cl_command_queue queue, std::string device_name,
                                             std::function<cl_mem()> image);

}  // namespace prism::opencl_gl
