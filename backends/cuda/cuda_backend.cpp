#include "backends/cuda/cuda_backend.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "backends/cuda/cuda_device.h"
#ifdef PRISM_CUDA_GL_INTEROP
#include "backends/cuda/cuda_gl_interop.h"
#endif
#include "core/device_filter.h"
#include "core/error.h"

namespace prism {
namespace {

std::string mebibytes(size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", double(bytes) / (1024.0 * 1024.0));
    return text;
}

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
}

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
        if (lower(d.name).find(lower(filter)) != std::string::npos) return d;
    throw Error("cuda: no device matches '" + filter + "' (devices: " + known + ")");
}

class CudaBackend final : public Backend {
public:
    CudaBackend(const cuda::DeviceDescription& device, const GlContextHandles* gl)
        : context_(device), memory_limit_(cuda::device_memory_limit()) {
        blocks_ = cuda::kBlocksPerMultiprocessor * static_cast<unsigned>(std::max(device.multiprocessors, 1));
        if (gl) set_up_gl_interop(*gl);
    }

    ~CudaBackend() override {
        gl_.reset();   // unregister the GL buffer while the context is alive
        for (void* pointer : pointers_) {
            try {
                context_.release(pointer);
            } catch (const Error&) {
                // A dead context (after a kernel fault) cannot free; the process exit reclaims the memory.
            }
        }
    }

    BackendInfo info() const override {
        const cuda::DeviceDescription& d = context_.device();
        BackendInfo info;
        info.name = "cuda";
        info.device = d.name;   // the bare name, as OpenCL and Vulkan report it: result files match across APIs
        info.driver = cuda::driver_version();
        info.api_version = cuda::runtime_version();
        info.device_memory = d.total_memory;
        info.max_buffer = d.total_memory;
        return info;
    }

    void allocate(DeviceArray array, size_t bytes) override {
        const size_t slot = size_t(array);
        if (pointers_[slot] && sizes_[slot] == bytes) return;
        const char* name = device_array_name(array);
        const cuda::DeviceDescription& d = context_.device();
        if (bytes > d.total_memory)
            throw Error(std::string("cuda: buffer '") + name + "' needs " + mebibytes(bytes) + " MiB but " + d.name +
                        " has only " + mebibytes(d.total_memory) + " MiB");
        // Free the old buffer first: its memory counts as available for the new one.
        context_.release(std::exchange(pointers_[slot], nullptr));
        allocated_ -= std::exchange(allocated_sizes_[slot], 0);
        sizes_[slot] = 0;

        // Never a zero-byte allocation: stages get a valid pointer even for an empty array (no textures, ...).
        const size_t device_bytes = std::max<size_t>(bytes, 16);
        size_t available = context_.free_memory();
        std::string limit_note;
        if (memory_limit_) {
            size_t left = *memory_limit_ > allocated_ ? *memory_limit_ - allocated_ : 0;
            if (left < available) {
                available = left;
                limit_note = " (PRISM_DEVICE_MEMORY_LIMIT=" + std::to_string(*memory_limit_) + ")";
            }
        }
        if (device_bytes > available)
            throw Error(std::string("cuda: buffer '") + name + "' needs " + mebibytes(bytes) + " MiB but only " +
                        mebibytes(available) + " MiB are free on " + d.name + limit_note);
        pointers_[slot] = context_.allocate(device_bytes, name);
        sizes_[slot] = bytes;
        allocated_sizes_[slot] = device_bytes;
        allocated_ += device_bytes;
    }

    void write(DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        check_range(array, bytes, offset);
        context_.copy_to_device(static_cast<char*>(pointers_[size_t(array)]) + offset, data, bytes);
    }

    void read(DeviceArray array, void* data, size_t bytes, size_t offset) override {
        check_range(array, bytes, offset);
        context_.copy_to_host(data, static_cast<const char*>(pointers_[size_t(array)]) + offset, bytes);
    }

    void zero(DeviceArray array) override {
        if (pointers_[size_t(array)]) context_.fill_zero(pointers_[size_t(array)], sizes_[size_t(array)]);
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
            gl_ = cuda::create_gl_interop(context_, [this] {
                return static_cast<const void*>(pointers_[size_t(DeviceArray::image)]);
            }, gl);
#else
        gl_reason_ = "CUDA-GL interop not built (no OpenGL headers at configure time)";
#endif
    }

    void check_range(DeviceArray array, size_t bytes, size_t offset) const {
        const size_t size = sizes_[size_t(array)];
        if (!pointers_[size_t(array)] || offset > size || bytes > size - offset)
            throw Error(std::string("cuda: access past the end of array '") + device_array_name(array) + "' (" +
                        std::to_string(offset) + "+" + std::to_string(bytes) + " of " + std::to_string(size) +
                        " bytes)");
    }

    cuda::DeviceContext context_;
    std::optional<size_t> memory_limit_;
    unsigned blocks_ = 0;
    std::array<void*, device_array_count> pointers_{};        // indexed by slot: what stages.cu receives
    std::array<size_t, device_array_count> sizes_{};          // bytes the caller asked for
    std::array<size_t, device_array_count> allocated_sizes_{};
    size_t allocated_ = 0;
    std::vector<StageTiming> pending_;
    std::unique_ptr<GlInterop> gl_;   // CUDA-GL, when the viewer asked and its GL context is on this device
    std::string gl_reason_;           // why gl_ is null
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
                                ", " + std::to_string(d.multiprocessors) + " SMs, " + mebibytes(d.total_memory) +
                                " MiB)");
        a.detail = a.available ? cuda::runtime_version() + ", driver " + cuda::driver_version() : no_device_reason(why);
        return a;
    };
    return factory;
}

}  // namespace prism
