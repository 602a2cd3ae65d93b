#include "backends/cuda/cuda_gl_interop.h"

#include <GL/gl.h>  // GLuint for cuda_gl_interop.h; no GL function is called here
#include <cuda.h>   // driver API types only: its functions come from cudaGetDriverEntryPointByVersion
#include <cuda_gl_interop.h>
#include <cuda_runtime.h>
#include <unistd.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "core/util/environment.h"
#include "core/util/error.h"

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
    std::string sync() const override { return "registered GL buffer, map/unmap on the CUDA stream"; }
    bool device_owns_memory() const override { return false; }
    bool needs_gl_idle_before_copy() const override { return false; }  // mapping waits for GL's use

    void attach_gl_buffer(uint32_t gl_buffer, size_t bytes) override {
        context_.bind();
        if (resource_) {
            cudaGraphicsUnregisterResource(std::exchange(resource_, nullptr));
            cudaGetLastError();
        }
        // Write-discard: CUDA never reads the old contents, so the driver need not preserve them.
        context_.check(
            cudaGraphicsGLRegisterBuffer(&resource_, GLuint(gl_buffer), cudaGraphicsRegisterFlagsWriteDiscard),
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
        if (status == cudaSuccess) status = cudaMemcpyAsync(target, image_(), bytes, cudaMemcpyDeviceToDevice, stream);
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

// The driver API calls of the external-memory path, resolved at run time through the runtime: prism links the
// CUDA runtime statically and never libcuda itself, so it still starts on machines without the driver.
struct VirtualMemoryApi {
    decltype(&cuMemGetAllocationGranularity) granularity = nullptr;
    decltype(&cuMemCreate) create = nullptr;
    decltype(&cuMemRelease) release = nullptr;
    decltype(&cuMemAddressReserve) reserve = nullptr;
    decltype(&cuMemAddressFree) free_address = nullptr;
    decltype(&cuMemMap) map = nullptr;
    decltype(&cuMemUnmap) unmap = nullptr;
    decltype(&cuMemSetAccess) set_access = nullptr;
    decltype(&cuMemExportToShareableHandle) export_handle = nullptr;
    decltype(&cuDeviceGet) device = nullptr;
    decltype(&cuDeviceGetAttribute) attribute = nullptr;
    std::string missing;  // the first entry point the driver did not give

    VirtualMemoryApi() {
        auto get = [this](auto& function, const char* name) {
            void* pointer = nullptr;
            cudaDriverEntryPointQueryResult found = cudaDriverEntryPointSymbolNotFound;
            if (cudaGetDriverEntryPointByVersion(name, &pointer, 12000, cudaEnableDefault, &found) != cudaSuccess ||
                found != cudaDriverEntryPointSuccess || !pointer) {
                cudaGetLastError();
                if (missing.empty()) missing = name;
                return;
            }
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(pointer);
        };
        get(granularity, "cuMemGetAllocationGranularity");
        get(create, "cuMemCreate");
        get(release, "cuMemRelease");
        get(reserve, "cuMemAddressReserve");
        get(free_address, "cuMemAddressFree");
        get(map, "cuMemMap");
        get(unmap, "cuMemUnmap");
        get(set_access, "cuMemSetAccess");
        get(export_handle, "cuMemExportToShareableHandle");
        get(device, "cuDeviceGet");
        get(attribute, "cuDeviceGetAttribute");
    }

    // Whether device `ordinal` can export memory as a POSIX fd (false when an entry point is missing).
    bool exports_fds(int ordinal) const {
        CUdevice handle = 0;
        int supported = 0;
        return missing.empty() && device(&handle, ordinal) == CUDA_SUCCESS &&
               attribute(&supported, CU_DEVICE_ATTRIBUTE_HANDLE_TYPE_POSIX_FILE_DESCRIPTOR_SUPPORTED, handle) ==
                   CUDA_SUCCESS &&
               supported != 0;
    }
};

// CUDA-GL through external memory: CUDA allocates the shared buffer (cuMemCreate, exportable as a POSIX fd), GL
// imports it (GL_EXT_memory_object_fd) as the buffer it draws from, and the frame's copy into it is one
// cudaMemcpyAsync on the stream — no per-frame cudaGraphicsMapResources/Unmap, which cost the render measurably
// (docs/viewer.md). No semaphore crosses over (CUDA exports none, GL exports none): the frame's own
// synchronisation (its counters read) orders GL's draw after the copy, and a GL fence the host waits on right
// before the next copy orders that copy after GL's draw.
class CudaExternalGlInterop final : public GlInterop {
public:
    CudaExternalGlInterop(DeviceContext& context, std::function<const void*()> image,
                          std::shared_ptr<const VirtualMemoryApi> api)
        : context_(context), image_(std::move(image)), api_(std::move(api)) {}
    ~CudaExternalGlInterop() override { release(); }

    std::string name() const override { return "CUDA-GL"; }
    std::string sync() const override {
        return "external memory (cuMemExportToShareableHandle + GL_EXT_memory_object_fd): the frame's stream sync, "
               "a GL fence before the next copy";
    }
    bool device_owns_memory() const override { return true; }
    bool needs_gl_idle_before_copy() const override { return true; }

    ExportedBuffer export_buffer(size_t bytes) override {
        release();
        context_.bind();
        const int device = context_.device().index;
        CUmemAllocationProp properties{};
        properties.type = CU_MEM_ALLOCATION_TYPE_PINNED;
        properties.location.type = CU_MEM_LOCATION_TYPE_DEVICE;
        properties.location.id = device;
        properties.requestedHandleTypes = CU_MEM_HANDLE_TYPE_POSIX_FILE_DESCRIPTOR;
        size_t granularity = 0;
        check(api_->granularity(&granularity, &properties, CU_MEM_ALLOC_GRANULARITY_MINIMUM),
              "cuMemGetAllocationGranularity");
        size_ = (bytes + granularity - 1) / granularity * granularity;
        try {
            check(api_->create(&handle_, size_, &properties, 0), "cuMemCreate (exportable)");
            created_ = true;
            check(api_->reserve(&address_, size_, granularity, 0, 0), "cuMemAddressReserve");
            check(api_->map(address_, size_, 0, handle_, 0), "cuMemMap");
            mapped_ = true;
            CUmemAccessDesc access{};
            access.location = properties.location;
            access.flags = CU_MEM_ACCESS_FLAGS_PROT_READWRITE;
            check(api_->set_access(address_, size_, &access, 1), "cuMemSetAccess");
            ExportedBuffer exported;
            int fd = -1;
            check(api_->export_handle(&fd, handle_, CU_MEM_HANDLE_TYPE_POSIX_FILE_DESCRIPTOR, 0),
                  "cuMemExportToShareableHandle");
            exported.memory_fd = fd;
            exported.allocation_size = size_;
            exported.dedicated = false;
            bytes_ = bytes;
            return exported;
        } catch (...) {
            release();
            throw;
        }
    }

    void copy_image(size_t bytes) override {
        if (!address_) throw Error("cuda: CUDA-GL copy before the buffer was exported");
        if (bytes > bytes_)
            throw Error("cuda: frame of " + std::to_string(bytes) + " bytes does not fit the shared buffer of " +
                        std::to_string(bytes_));
        wait_for_gl_idle();  // GL's draw of the last shown frame has read the buffer
        context_.bind();
        context_.check(cudaMemcpyAsync(reinterpret_cast<void*>(address_), image_(), bytes, cudaMemcpyDeviceToDevice,
                                       static_cast<cudaStream_t>(context_.stream())),
                       "device-to-device copy into the shared buffer");
    }

private:
    void check(CUresult result, const char* what) const {
        if (result == CUDA_SUCCESS) return;
        throw Error(std::string("cuda: ") + what + " failed on " + context_.device().name + " (CUresult " +
                    std::to_string(int(result)) + ")");
    }

    void release() {
        if (!created_) return;
        context_.bind();
        // No copy may still write it: the stream's work is waited for (GL holds its own reference through the fd).
        cudaStreamSynchronize(static_cast<cudaStream_t>(context_.stream()));
        cudaGetLastError();
        if (mapped_) api_->unmap(address_, size_);
        if (address_) api_->free_address(address_, size_);
        api_->release(handle_);
        created_ = mapped_ = false;
        address_ = 0;
        bytes_ = 0;
    }

    DeviceContext& context_;
    std::function<const void*()> image_;
    std::shared_ptr<const VirtualMemoryApi> api_;
    CUmemGenericAllocationHandle handle_ = 0;
    CUdeviceptr address_ = 0;
    size_t size_ = 0, bytes_ = 0;
    bool created_ = false, mapped_ = false;
};

}  // namespace

std::string gl_context_check(const DeviceContext& context, const std::string& gl_renderer) {
    context.bind();
    unsigned int count = 0;
    int devices[8] = {};
    cudaError_t status = cudaGLGetDevices(&count, devices, 8, cudaGLDeviceListAll);
    if (status != cudaSuccess) {
        cudaGetLastError();
        return "GL runs on " + gl_renderer + ", not on a CUDA device (cudaGLGetDevices: " + cudaGetErrorName(status) +
               ")";
    }
    for (unsigned int i = 0; i < count && i < 8; ++i)
        if (devices[i] == context.device().index) return "";
    return "GL runs on " + gl_renderer + ", another device than CUDA device " + std::to_string(context.device().index);
}

std::unique_ptr<GlInterop> create_gl_interop(DeviceContext& context, std::function<const void*()> image,
                                             const GlContextHandles& gl) {
    // External memory where GL can import it and the driver exports POSIX fds; the registered GL buffer (map/unmap
    // per frame) otherwise, or when PRISM_CUDA_GL=register asks for it (to measure one against the other).
    bool registered = setting(Setting::CudaGl) == "register";
    if (!registered && gl.memory_object_fd) {
        context.bind();
        auto api = std::make_shared<const VirtualMemoryApi>();
        if (api->exports_fds(context.device().index))
            return std::make_unique<CudaExternalGlInterop>(context, std::move(image), std::move(api));
    }
    return std::make_unique<CudaGlInterop>(context, std::move(image));
}

}  // namespace prism::cuda
