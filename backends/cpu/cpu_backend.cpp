#include "backends/cpu/cpu_backend.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>
#include <utility>

#include "core/error.h"
#include "core/thread_pool.h"
#include "kernels/stages.h"

thread_local RtCpuGrid rt_cpu_grid;

namespace prism {
namespace {

std::string cpu_name() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line))
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
            return line.substr(line.find(':') + 2);
    return "host CPU";
}

class CpuBackend final : public Backend {
public:
    explicit CpuBackend(unsigned threads) : pool_(threads) {}

    BackendInfo info() const override {
        BackendInfo info;
        info.name = "cpu";
        info.device = cpu_name() + " (" + std::to_string(pool_.size()) + " threads)";
        info.driver = "host";
        info.api_version = "C++20";
        info.max_buffer = size_t(1) << 40;
        return info;
    }

    void allocate(DeviceArray array, size_t bytes) override {
        auto& buffer = buffers_[size_t(array)];
        if (buffer.size() != bytes) {
            // std::vector<float4> keeps the 16-byte alignment every element type needs.
            buffer.assign((bytes + sizeof(float4) - 1) / sizeof(float4), float4{});
            sizes_[size_t(array)] = bytes;
        }
    }
    void write(DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        check_range(array, bytes, offset);
        std::memcpy(reinterpret_cast<char*>(buffers_[size_t(array)].data()) + offset, data, bytes);
    }
    void read(DeviceArray array, void* data, size_t bytes, size_t offset) override {
        check_range(array, bytes, offset);
        std::memcpy(data, reinterpret_cast<const char*>(buffers_[size_t(array)].data()) + offset, bytes);
    }
    void zero(DeviceArray array) override {
        std::memset(buffers_[size_t(array)].data(), 0, sizes_[size_t(array)]);
    }

    void enqueue(Stage stage, uint32_t depth) override {
        KernelGlobals kg = globals();
        auto start = std::chrono::steady_clock::now();
        std::atomic<uint32_t> cursor{0};
        // Chunks small enough to balance glass against background, large enough to amortise the atomic.
        const uint32_t chunk = stage == Stage::Generate || stage == Stage::Resolve ? 1024 : 64;
        pool_.run([&](unsigned) {
            rt_cpu_grid = RtCpuGrid{&cursor, chunk};
            switch (stage) {
                case Stage::Generate: rt_kernel_generate(kg, depth); break;
                case Stage::Intersect: rt_kernel_intersect(kg, depth); break;
                case Stage::Miss: rt_kernel_miss(kg, depth); break;
                case Stage::Shade: rt_kernel_shade(kg, depth); break;
                case Stage::Shadow: rt_kernel_shadow(kg, depth); break;
                case Stage::Resolve: rt_kernel_resolve(kg, depth); break;
                case Stage::Count: break;
            }
        });
        timings_.push_back(StageTiming{stage, depth,
                                       std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
    }

    std::vector<StageTiming> finish() override { return std::exchange(timings_, {}); }

    GlInteropOffer gl_interop() override { return {nullptr, "the frame is already in host memory"}; }

private:
    void check_range(DeviceArray array, size_t bytes, size_t offset) const {
        if (offset + bytes > sizes_[size_t(array)])
            throw Error(std::string("cpu: access past the end of array '") + device_array_name(array) + "'");
    }

    KernelGlobals globals() {
        KernelGlobals kg{};
#define RT_DATA_ARRAY(slot, type, name, access) \
    kg.name = reinterpret_cast<type*>(buffers_[size_t(DeviceArray::name)].data());
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
        return kg;
    }

    ThreadPool pool_;
    std::array<std::vector<float4>, device_array_count> buffers_;
    std::array<size_t, device_array_count> sizes_{};
    std::vector<StageTiming> timings_;
};

}  // namespace

BackendFactory cpu_backend_factory() {
    BackendFactory factory;
    factory.name = "cpu";
    // No GL interop: the frame is in host memory already, and the host copy is the texture upload it needs.
    factory.create = [](const std::string& filter, const GlContextHandles*) -> std::unique_ptr<Backend> {
        // "cpu:N" selects N threads; anything else names no device.
        unsigned threads = 0;
        if (!filter.empty()) {
            try {
                threads = static_cast<unsigned>(std::stoul(filter));
            } catch (...) {
                throw Error("cpu: device '" + filter + "' is not a thread count (use cpu or cpu:N)");
            }
        }
        return std::make_unique<CpuBackend>(threads);
    };
    factory.probe = [] {
        BackendAvailability a;
        a.name = "cpu";
        a.available = true;
        a.devices = {cpu_name() + " (" + std::to_string(std::thread::hardware_concurrency()) + " threads)"};
        a.detail = "kernels/ compiled as C++ on a thread pool";
        return a;
    };
    return factory;
}

}  // namespace prism
