#include "backends/cuda/cuda_backend.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "backends/cuda/cuda_device.h"
#include "backends/cuda/cuda_launch.h"
#ifdef PRISM_CUDA_GL_INTEROP
#include "backends/cuda/cuda_gl_interop.h"
#endif
#include "core/render/device_array_book.h"
#include "core/render/device_filter.h"
#include "core/util/error.h"

namespace prism {
namespace {

std::string no_device_reason(const std::string& why) { return "no CUDA device (" + why + ")"; }

cuda::DeviceDescription select_device(const std::string& filter) {
    std::string why;
    std::vector<cuda::DeviceDescription> devices = cuda::list_devices(why);
    if (devices.empty()) throw Error("cuda: " + no_device_reason(why));
    if (filter.empty()) return devices.front();
    std::string known;
    for (const auto& d : devices) known += (known.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
    if (std::optional<size_t> index = device_index(filter)) {
        if (*index < devices.size()) return devices[*index];
        throw Error("cuda: no device " + filter + " (devices: " + known + ")");
    }
    for (const auto& d : devices)
        if (name_matches(d.name, filter)) return d;
    throw Error("cuda: no device matches '" + filter + "' (devices: " + known + ")");
}

class CudaBackend final : public Backend {
public:
    CudaBackend(const cuda::DeviceDescription& device, const GlContextHandles* gl)
        : context_(device), book_("cuda", device.name, device.total_memory) {
        blocks_ = cuda::kBlocksPerMultiprocessor * static_cast<unsigned>(std::max(device.multiprocessors, 1));
        if (gl) set_up_gl_interop(*gl);
    }

    ~CudaBackend() override {
        gl_.reset();  // unregister the GL buffer while the context is alive
        for (size_t slot = 0; slot < device_array_count; ++slot) {
            try {
                context_.release(pointers_[slot]);
                context_.release_host(pinned_[slot].pointer);
            } catch (const Error&) {
                // A dead context (after a kernel fault) cannot free; the process exit reclaims the memory.
            }
        }
    }

    BackendInfo info() const override {
        const cuda::DeviceDescription& d = context_.device();
        BackendInfo info;
        info.name = "cuda";
        info.device = d.name;  // the bare name, as OpenCL and Vulkan report it: result files match across APIs
        info.driver = cuda::driver_version();
        info.api_version = cuda::runtime_version();
        info.device_memory = d.total_memory;
        info.max_buffer = d.total_memory;
        return info;
    }

    KernelResources kernel_resources() const override {
        KernelResources resources{"cudaFuncGetAttributes", {}};
        context_.bind();
        for (size_t i = 0; i < stage_count; ++i) {
            cuda::StageAttributes a;
            context_.check(cuda::stage_attributes(unsigned(i), &a),
                           std::string("reading the attributes of stage '") + stage_name(Stage(i)) + "'");
            StageResources stage;
            stage.stage = Stage(i);
            stage.registers = a.registers;
            stage.private_bytes = a.local_bytes;
            stage.shared_bytes = a.shared_bytes;
            resources.stages.push_back(stage);
        }
        return resources;
    }

    void allocate(DeviceArray array, size_t bytes) override {
        const size_t slot = size_t(array);
        if (book_.allocated(array) && book_.size(array) == bytes) return;
        const char* name = device_array_name(array);
        const cuda::DeviceDescription& d = context_.device();
        // Never a zero-byte allocation: stages get a valid pointer even for an empty array (no textures, ...).
        const size_t device_bytes = std::max<size_t>(bytes, 16);
        book_.check_fits(array, bytes, device_bytes);
        // Free the old buffer first: its memory counts as available for the new one.
        context_.release(std::exchange(pointers_[slot], nullptr));
        book_.forget(array);
        const size_t free = context_.free_memory();
        if (device_bytes > free)
            throw Error(std::string("cuda: buffer '") + name + "' needs " + mib_text(bytes) + " but only " +
                        mib_text(free) + " are free on " + d.name);
        pointers_[slot] = context_.allocate(device_bytes, name);
        book_.record(array, bytes, device_bytes);
    }

    void write(DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        book_.check_range(array, bytes, offset);
        context_.copy_to_device(static_cast<char*>(pointers_[size_t(array)]) + offset, data, bytes);
    }

    void read(DeviceArray array, void* data, size_t bytes, size_t offset) override {
        book_.check_range(array, bytes, offset);
        context_.copy_to_host(data, static_cast<const char*>(pointers_[size_t(array)]) + offset, bytes);
    }

    const void* read_pinned(DeviceArray array, size_t bytes) override {
        book_.check_range(array, bytes, 0);
        PinnedHost& host = pinned_[size_t(array)];
        if (host.bytes < bytes) {
            context_.release_host(std::exchange(host.pointer, nullptr));
            host.bytes = 0;
            host.pointer = context_.allocate_host(bytes, device_array_name(array));
            host.bytes = bytes;
        }
        context_.copy_to_host(host.pointer, pointers_[size_t(array)], bytes);
        return host.pointer;
    }

    void zero(DeviceArray array) override {
        if (pointers_[size_t(array)]) context_.fill_zero(pointers_[size_t(array)], book_.size(array));
    }

    void enqueue(Stage stage, uint32_t depth) override {
        if (stage >= Stage::Count) throw Error("cuda: unknown stage");
        context_.launch(static_cast<unsigned>(stage), stage_name(stage), pointers_.data(), depth, blocks_,
                        cuda::kThreadsPerBlock);
        pending_.push_back(StageTiming{stage, depth, 0.0});
    }

    std::vector<StageTiming> finish() override {
        std::vector<StageTiming> timings = std::exchange(pending_, {});
        std::vector<double> ms = context_.synchronize_and_collect_ms();
        for (size_t i = 0; i < timings.size() && i < ms.size(); ++i) timings[i].milliseconds = ms[i];
        return timings;
    }

    GlInteropOffer gl_interop() override {
        if (gl_) return {gl_.get(), ""};
        return {nullptr, gl_reason_.empty() ? "GL interop was not requested" : gl_reason_};
    }

private:
    void set_up_gl_interop([[maybe_unused]] const GlContextHandles& gl) {
#ifdef PRISM_CUDA_GL_INTEROP
        gl_reason_ = cuda::gl_context_check(context_, gl.renderer);
        if (gl_reason_.empty())
            gl_ = cuda::create_gl_interop(
                context_, [this] { return static_cast<const void*>(pointers_[size_t(DeviceArray::image)]); }, gl);
#else
        gl_reason_ = "CUDA-GL interop not built (no OpenGL headers at configure time)";
#endif
    }

    cuda::DeviceContext context_;
    DeviceArrayBook book_;
    unsigned blocks_ = 0;
    std::array<void*, device_array_count> pointers_{};  // indexed by slot: what stages.cu receives
    struct PinnedHost {
        void* pointer = nullptr;
        size_t bytes = 0;
    };
    std::array<PinnedHost, device_array_count> pinned_{};  // read_pinned's host memory, by slot
    std::vector<StageTiming> pending_;
    std::unique_ptr<GlInterop> gl_;  // CUDA-GL, when the viewer asked and its GL context is on this device
    std::string gl_reason_;          // why gl_ is null
};

}  // namespace

BackendFactory cuda_backend_factory() {
    BackendFactory factory;
    factory.name = "cuda";
    factory.create = [](const std::string& filter, const GlContextHandles* gl) -> std::unique_ptr<Backend> {
        return std::make_unique<CudaBackend>(select_device(filter), gl);
    };
    factory.probe = [] {
        BackendAvailability a;
        a.name = "cuda";
        std::string why;
        std::vector<cuda::DeviceDescription> devices = cuda::list_devices(why);
        a.available = !devices.empty();
        for (const auto& d : devices)
            a.devices.push_back(d.name + " (sm_" + std::to_string(d.compute_major) + std::to_string(d.compute_minor) +
                                ", " + std::to_string(d.multiprocessors) + " SMs, " + mib_text(d.total_memory) + ")");
        a.detail = a.available ? cuda::runtime_version() + ", driver " + cuda::driver_version() : no_device_reason(why);
        return a;
    };
    return factory;
}

}  // namespace prism
