#include "backends/cpu/cpu_backend.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>

#include <sys/mman.h>
#include <thread>
#include <utility>

#include "backends/cpu/cpu_stages.h"
#include "core/render/device_array_book.h"
#include "core/util/environment.h"
#include "core/util/error.h"
#include "core/util/thread_pool.h"

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

// The stages built for the best instruction set this CPU runs; PRISM_CPU_ISA=baseline|avx2 picks one (tests, and
// measuring what AVX2 gains).
struct StageSet {
    cpu::StageRunner run = cpu::run_stage_baseline;
    std::string isa = "baseline";
};

StageSet pick_stages() {
    const std::string isa = setting_choice(Setting::CpuIsa, {"baseline", "avx2"}, "cpu");
#if defined(PRISM_CPU_AVX2)
    bool avx2 = __builtin_cpu_supports("avx2");
    if (isa == "avx2" && !avx2) throw Error("cpu: PRISM_CPU_ISA=avx2, but this CPU has no AVX2");
    if (avx2 && isa != "baseline") return StageSet{cpu::run_stage_avx2, "avx2"};
#else
    if (isa == "avx2") throw Error("cpu: PRISM_CPU_ISA=avx2, but this build has no AVX2 stages");
#endif
    return StageSet{};
}

// Device arrays: cache-line aligned, and arrays of 2 MiB or more on 2 MiB boundaries with transparent huge pages
// requested (madvise), so a traversal jumping through a large BVH misses the TLB less.
template <class T>
struct DeviceArrayAllocator {
    using value_type = T;
    static constexpr size_t kHugePage = size_t(2) << 20;
    DeviceArrayAllocator() = default;
    template <class U>
    DeviceArrayAllocator(const DeviceArrayAllocator<U>&) {}
    static size_t alignment(size_t bytes) { return bytes >= kHugePage ? kHugePage : 64; }
    T* allocate(size_t n) {
        size_t bytes = n * sizeof(T);
        void* p = ::operator new(bytes, std::align_val_t(alignment(bytes)));
#if defined(MADV_HUGEPAGE)
        if (bytes >= kHugePage) madvise(p, bytes, MADV_HUGEPAGE);  // a hint: failure changes nothing
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t n) { ::operator delete(p, std::align_val_t(alignment(n * sizeof(T)))); }
    bool operator==(const DeviceArrayAllocator&) const { return true; }
};

class CpuBackend final : public Backend {
public:
    explicit CpuBackend(unsigned threads) : pool_(threads), stages_(pick_stages()) {}

    BackendInfo info() const override {
        BackendInfo info;
        info.name = "cpu";
        info.device = cpu_name() + " (" + std::to_string(pool_.size()) + " threads, " + stages_.isa + ")";
        info.driver = "host";
        info.api_version = "C++20";
        info.max_buffer = size_t(1) << 40;
        return info;
    }

    void allocate(DeviceArray array, size_t bytes) override {
        auto& buffer = buffers_[size_t(array)];
        if (book_.allocated(array) && book_.size(array) == bytes) return;
        // Cache-line aligned: a 256-byte wide BVH node then spans exactly four lines.
        buffer.assign((bytes + sizeof(float4) - 1) / sizeof(float4), float4{});
        book_.record(array, bytes, buffer.size() * sizeof(float4));
    }
    void write(DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        book_.check_range(array, bytes, offset);
        if (bytes == 0) return;  // an empty array has no storage: memcpy must not see its null pointer
        std::memcpy(reinterpret_cast<char*>(buffers_[size_t(array)].data()) + offset, data, bytes);
    }
    void read(DeviceArray array, void* data, size_t bytes, size_t offset) override {
        book_.check_range(array, bytes, offset);
        if (bytes == 0) return;
        std::memcpy(data, reinterpret_cast<const char*>(buffers_[size_t(array)].data()) + offset, bytes);
    }
    // The arrays are host memory already: the array itself, which no stage changes before the next enqueue.
    const void* read_pinned(DeviceArray array, size_t bytes) override {
        book_.check_range(array, bytes, 0);
        return buffers_[size_t(array)].data();
    }
    void zero(DeviceArray array) override {
        if (book_.size(array) != 0) std::memset(buffers_[size_t(array)].data(), 0, book_.size(array));
    }

    void enqueue(Stage stage, uint32_t depth) override {
        KernelGlobals kg = globals();
        auto start = std::chrono::steady_clock::now();
        std::atomic<uint32_t> cursor{0};
        // The smallest range a worker takes (RT_GRID_LOOP guides the larger ones): small enough to balance glass
        // against background at the end of a launch, large enough to amortise the atomic; the once-a-frame stages
        // do the same small work per pixel.
        const uint32_t chunk = stage_pass(stage) == StagePass::Bounce ? 64 : 1024;
        const uint32_t workers = pool_.size();
        pool_.run([&](unsigned) {
            rt_cpu_grid = RtCpuGrid{&cursor, chunk, workers};
            stages_.run(stage, kg, depth);
        });
        timings_.push_back(StageTiming{
            stage, depth, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
    }

    std::vector<StageTiming> finish() override { return std::exchange(timings_, {}); }

    GlInteropOffer gl_interop() override { return {nullptr, "the frame is already in host memory"}; }

private:
    KernelGlobals globals() {
        KernelGlobals kg{};
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    kg.name = reinterpret_cast<type*>(buffers_[size_t(DeviceArray::name)].data());
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
        return kg;
    }

    ThreadPool pool_;
    StageSet stages_;
    std::array<std::vector<float4, DeviceArrayAllocator<float4>>, device_array_count> buffers_;
    DeviceArrayBook book_{"cpu", "", std::nullopt};  // sizes and range checks; host memory has its own guard
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
