#include "backends/cuda/cuda_gl_interop.h"

#include <GL/gl.h>   // GLuint for cuda_gl_interop.h; no GL function is called here
#include <cuda_gl_interop.h>
#include <cuda_runtime.h>

#include <utility>

#include "core/error.h"

namespace prism::cuda {
namespace {

class CudaGlInterop final : public GlInterop {
public:
    CudaGlInterop(DeviceContext& context, std::function<const void*()> image)
        : context_(context), image_(std::move(image)) {}

    ~CudaGlInterop() override {
        if (!resource_) return;
        context_.bind();
        // Unregistering waits for the work that used it; a failure here (a dead context) leaves nothing to free.
        cudaGraphicsUnregisterResource(resource_);
        cudaGetLastError();
    }

    std::string name() const override { return "CUDA-GL"; }
    std::string sync() const override { return "map/unmap on the CUDA stream"; }
    bool device_owns_memory() const override { return false; }
    bool needs_gl_idle_before_copy() const override { return false; }   // mapping waits for GL's use

    void attach_gl_buffer(uint32_t gl_buffer, size_t bytes) override {
        context_.bind();
        if (resource_) {
            cudaGraphicsUnregisterResource(std::exchange(resource_, nullptr));
            cudaGetLastError();
        }
        // Write-discard: CUDA never reads the old contents, so the driver need not preserve them.
        context_.check(cudaGraphicsGLRegisterBuffer(&resource_, GLuint(gl_buffer), cudaGraphicsRegisterFlagsWriteDiscard),
                       "cudaGraphicsGLRegisterBuffer of GL buffer " + std::to_string(gl_buffer));
        bytes_ = bytes;
    }

    void copy_image(size_t bytes) override {
        if (!resource_) throw Error("cuda: CUDA-GL copy before a GL buffer was attached");
        if (bytes > bytes_)
            throw Error("cuda: frame of " + std::to_string(bytes) + " bytes does not fit the GL buffer of " +
                        std::to_string(bytes_));
        context_.bind();
        auto stream = static_cast<cudaStream_t>(context_.stream());
        context_.check(cudaGraphicsMapResources(1, &resource_, stream), "cudaGraphicsMapResources");
        void* target = nullptr;
        size_t mapped = 0;
        cudaError_t status = cudaGraphicsResourceGetMappedPointer(&target, &mapped, resource_);
        if (status == cudaSuccess)
            status = cudaMemcpyAsync(target, image_(), bytes, cudaMemcpyDeviceToDevice, stream);
        // Always unmap, even after a failed copy: a mapped buffer would block GL. Unmapping on the stream makes
        // GL's later use of the buffer wait for the copy, with no host synchronisation.
        cudaError_t unmapped = cudaGraphicsUnmapResources(1, &resource_, stream);
        context_.check(status, "device-to-device copy into the GL buffer");
        context_.check(unmapped, "cudaGraphicsUnmapResources");
    }

private:
    DeviceContext& context_;
    std::function<const void*()> image_;
    cudaGraphicsResource_t resource_ = nullptr;
    size_t bytes_ = 0;
};

}  // namespace

std::string gl_context_check(const DeviceContext& context, const std::string& gl_renderer) {
    context.bind();
    unsigned int count = 0;
    int devices[8] = {};
    cudaError_t status = cudaGLGetDevices(&count, devices, 8, cudaGLDeviceListAll);
    if (status != cudaSuccess) {
        cudaGetLastError();
        return "GL runs on " + gl_renderer + ", not on a CUDA device (cudaGLGetDevices: " +
               cudaGetErrorName(status) + ")";
    }
    for (unsigned int i = 0; i < count && i < 8; ++i)
        if (devices[i] == context.device().index) return "";
    return "GL runs on " + gl_renderer + ", another device than CUDA device " +
           std::to_string(context.device().index);
}

std::unique_ptr<GlInterop> create_gl_interop(DeviceContext& context, std::function<const void*()> image) {
    return std::make_unique<CudaGlInterop>(context, std::move(image));
}

}  // namespace prism::cuda
