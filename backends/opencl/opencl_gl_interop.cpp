#include "backends/opencl/opencl_gl_interop.h"

#include <CL/cl_gl.h>

#include <algorithm>
#include <utility>

#include "backends/opencl/opencl_device.h"
#include "core/util/error.h"

namespace prism::opencl_gl {
namespace {

void check(cl_int err, const char* what, const std::string& device) {
    if (err != CL_SUCCESS)
        throw Error(std::string("opencl: ") + what + " failed on " + device + " (error " + std::to_string(err) + ")");
}

class OpenClGlInterop final : public GlInterop {
public:
    OpenClGlInterop(cl_context context, cl_command_queue queue, std::string device, std::function<cl_mem()> image)
        : context_(context), queue_(queue), device_(std::move(device)), image_(std::move(image)) {}
    ~OpenClGlInterop() override {
        if (shared_) clReleaseMemObject(shared_);
    }

    std::string name() const override { return "OpenCL-GL"; }
    std::string sync() const override { return "GL fence, acquire/release in the frame's queue"; }
    bool device_owns_memory() const override { return false; }
    // cl_khr_gl_sharing leaves it to the application to finish GL's use of the buffer before the acquire.
    bool needs_gl_idle_before_copy() const override { return true; }

    void attach_gl_buffer(uint32_t gl_buffer, size_t bytes) override {
        if (shared_) clReleaseMemObject(std::exchange(shared_, nullptr));
        cl_int err = CL_SUCCESS;
        shared_ = clCreateFromGLBuffer(context_, CL_MEM_WRITE_ONLY, gl_buffer, &err);
        check(err, "clCreateFromGLBuffer", device_);
        bytes_ = bytes;
    }

    void copy_image(size_t bytes) override {
        if (!shared_) throw Error("opencl: OpenCL-GL copy before a GL buffer was attached");
        if (bytes > bytes_)
            throw Error("opencl: frame of " + std::to_string(bytes) + " bytes does not fit the GL buffer of " +
                        std::to_string(bytes_));
        wait_for_gl_idle();  // cl_khr_gl_sharing: GL must be done with the buffer before the acquire
        check(clEnqueueAcquireGLObjects(queue_, 1, &shared_, 0, nullptr, nullptr), "clEnqueueAcquireGLObjects",
              device_);
        cl_int copied = clEnqueueCopyBuffer(queue_, image_(), shared_, 0, 0, bytes, 0, nullptr, nullptr);
        // Released even after a failed copy, so GL can use the buffer again.
        cl_int released = clEnqueueReleaseGLObjects(queue_, 1, &shared_, 0, nullptr, nullptr);
        check(copied, "clEnqueueCopyBuffer into the GL buffer", device_);
        check(released, "clEnqueueReleaseGLObjects", device_);
        // Without cl_khr_gl_event the portable guarantee that GL sees the copy is that it has finished: the frame's
        // blocking read of its counters, right after this on the in-order queue, is that wait.
    }

private:
    cl_context context_;
    cl_command_queue queue_;
    std::string device_;
    std::function<cl_mem()> image_;
    cl_mem shared_ = nullptr;
    size_t bytes_ = 0;
};

}  // namespace

ContextSharing context_properties(cl_platform_id platform, cl_device_id device, const std::string& platform_name,
                                  const std::string& device_name, const GlContextHandles& gl) {
    ContextSharing sharing;
    if (!opencl::device_has_extension(device, "cl_khr_gl_sharing")) {
        sharing.reason = platform_name + " has no cl_khr_gl_sharing";
        return sharing;
    }
    // The GL context is GLX (a window) or EGL (prism view --headless): cl_khr_gl_sharing names both.
    std::vector<cl_context_properties> properties;
    if (gl.glx_context && gl.x11_display) {
        properties = {CL_GL_CONTEXT_KHR, cl_context_properties(gl.glx_context), CL_GLX_DISPLAY_KHR,
                      cl_context_properties(gl.x11_display)};
    } else if (gl.egl_context && gl.egl_display) {
        properties = {CL_GL_CONTEXT_KHR, cl_context_properties(gl.egl_context), CL_EGL_DISPLAY_KHR,
                      cl_context_properties(gl.egl_display)};
    } else {
        sharing.reason = "the GL context is neither a GLX nor an EGL context (cl_khr_gl_sharing needs one)";
        return sharing;
    }
    properties.insert(properties.end(), {CL_CONTEXT_PLATFORM, cl_context_properties(platform), 0});
    // Which devices can share with this GL context: with several GPUs, GL may run on another one.
    auto devices_for_gl = reinterpret_cast<clGetGLContextInfoKHR_fn>(
        clGetExtensionFunctionAddressForPlatform(platform, "clGetGLContextInfoKHR"));
    if (devices_for_gl) {
        cl_device_id devices[16] = {};
        size_t size = 0;
        cl_int err = devices_for_gl(properties.data(), CL_DEVICES_FOR_GL_CONTEXT_KHR, sizeof devices, devices, &size);
        if (err != CL_SUCCESS) {
            sharing.reason = "clGetGLContextInfoKHR found no device for GL on " + gl.renderer + " (error " +
                             std::to_string(err) + ")";
            return sharing;
        }
        cl_device_id* end = devices + std::min<size_t>(size / sizeof(cl_device_id), 16);
        if (std::find(devices, end, device) == end) {
            sharing.reason = "GL runs on " + gl.renderer + ", not on " + device_name;
            return sharing;
        }
    }
    sharing.properties = std::move(properties);
    return sharing;
}

std::unique_ptr<GlInterop> create_gl_interop(cl_context context, cl_command_queue queue, std::string device_name,
                                             std::function<cl_mem()> image) {
    return std::make_unique<OpenClGlInterop>(context, queue, std::move(device_name), std::move(image));
}

}  // namespace prism::opencl_gl
