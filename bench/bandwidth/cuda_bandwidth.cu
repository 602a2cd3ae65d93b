// CUDA: every device. Pageable copies use malloc'd memory, pinned copies cudaMallocHost memory; all copies are
// cudaMemcpyAsync on one stream between two cudaEvents (device timer), with the host clock around issue + sync.
#include <cuda_runtime.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#define RT_CUDA
#include "kernels/bandwidth_copy.h"
#undef RT_CUDA

#include "backends/cuda/cuda_device.h"
#include "bench/bandwidth/api_runners.h"
#include "bench/bandwidth/copy_device.h"
#include "bench/bandwidth/pci_link.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bandwidth/sweep.h"
#include "core/util/error.h"

// The CUDA wrapper of the shared copy kernel: its two buffers and the element count.
__global__ void bandwidth_copy_kernel(uint4* source, uint4* destination, unsigned count) {
    BandwidthBuffers kg;
    kg.bandwidth_src = source;
    kg.bandwidth_dst = destination;
    rt_bandwidth_copy(kg, count);
}

namespace prism::bandwidth {
namespace {

using Clock = std::chrono::steady_clock;

std::string version_text(int version) {
    return std::to_string(version / 1000) + "." + std::to_string(version % 1000 / 10);
}

class CudaDevice final : public CopyDevice {
public:
    explicit CudaDevice(int ordinal) : ordinal_(ordinal) {
        check(cudaSetDevice(ordinal_), "cudaSetDevice");
        check(cudaGetDeviceProperties(&properties_, ordinal_), "cudaGetDeviceProperties");
        check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
        check(cudaEventCreate(&start_), "cudaEventCreate");
        check(cudaEventCreate(&stop_), "cudaEventCreate");
    }
    ~CudaDevice() override {
        release();
        cudaEventDestroy(start_);
        cudaEventDestroy(stop_);
        cudaStreamDestroy(stream_);
    }

    DeviceResult describe() const override {
        DeviceResult result;
        result.api = "cuda";
        result.device = properties_.name;
        result.platform = "CUDA";
        int runtime = 0, driver = 0;
        cudaRuntimeGetVersion(&runtime);
        cudaDriverGetVersion(&driver);
        result.driver = cuda::driver_version();
        result.api_version = "CUDA runtime " + version_text(runtime) + ", driver API " + version_text(driver);
        result.pci_address = pci_address(properties_.pciDomainID, properties_.pciBusID, properties_.pciDeviceID, 0);
        result.device_memory = properties_.totalGlobalMem;
        int memory_clock_khz = 0;
        cudaDeviceGetAttribute(&memory_clock_khz, cudaDevAttrMemoryClockRate, ordinal_);
        if (memory_clock_khz > 0 && properties_.memoryBusWidth > 0)  // double data rate: 2 transfers per clock
            result.memory_spec_gbps = memory_clock_khz * 1e3 * 2.0 * properties_.memoryBusWidth / 8.0 * 1e-9;
        result.details = {"pinned: cudaMallocHost; copies: cudaMemcpyAsync on one stream; timer: cudaEvent"};
        return result;
    }

    std::string cannot_fit(size_t bytes) const override {
        size_t free = 0, total = 0;
        cudaSetDevice(ordinal_);
        if (cudaMemGetInfo(&free, &total) == cudaSuccess && 2 * bytes + (size_t(64) << 20) > free)
            return "two buffers exceed free device memory (" + format_size(free) + ")";
        return "";
    }
    std::string kernel_cannot_fit(size_t) const override { return ""; }

    void allocate(size_t bytes, std::byte* pageable) override {
        check(cudaSetDevice(ordinal_), "cudaSetDevice");
        bytes_ = bytes;
        pageable_ = pageable;
        allocation(cudaMalloc(&buffer_a_, bytes), "device buffer A");
        allocation(cudaMalloc(&buffer_b_, bytes), "device buffer B");
        allocation(cudaMallocHost(&pinned_, bytes), "pinned host buffer (cudaMallocHost)");
    }
    void release() override {
        if (buffer_a_) cudaFree(buffer_a_);
        if (buffer_b_) cudaFree(buffer_b_);
        if (pinned_) cudaFreeHost(pinned_);
        buffer_a_ = buffer_b_ = nullptr;
        pinned_ = nullptr;
    }
    std::byte* pinned_upload() override { return static_cast<std::byte*>(pinned_); }
    std::byte* pinned_download() override { return static_cast<std::byte*>(pinned_); }

    Timed upload(Memory host) override {
        return timed(
            [&] { return cudaMemcpyAsync(buffer_a_, host_pointer(host), bytes_, cudaMemcpyHostToDevice, stream_); });
    }
    Timed download(Memory host) override {
        return timed(
            [&] { return cudaMemcpyAsync(host_pointer(host), buffer_a_, bytes_, cudaMemcpyDeviceToHost, stream_); });
    }
    Timed copy_buffer() override {
        return timed([&] { return cudaMemcpyAsync(buffer_b_, buffer_a_, bytes_, cudaMemcpyDeviceToDevice, stream_); });
    }
    Timed copy_kernel() override {
        unsigned count = static_cast<unsigned>(bytes_ / 16);
        // Same grid rule in every API: one element per thread, at most 65535 groups (then the loop strides).
        unsigned groups = std::min<unsigned>((count + RT_BANDWIDTH_GROUP_SIZE - 1) / RT_BANDWIDTH_GROUP_SIZE, 65535u);
        return timed([&] {
            bandwidth_copy_kernel<<<groups, RT_BANDWIDTH_GROUP_SIZE, 0, stream_>>>(
                static_cast<uint4*>(buffer_a_), static_cast<uint4*>(buffer_b_), count);
            return cudaGetLastError();
        });
    }
    void clear_destination() override {
        check(cudaMemsetAsync(buffer_b_, 0, bytes_, stream_), "cudaMemsetAsync");
        check(cudaStreamSynchronize(stream_), "cudaStreamSynchronize");
    }
    void read_destination() override {
        check(cudaMemcpy(pageable_, buffer_b_, bytes_, cudaMemcpyDeviceToHost), "cudaMemcpy");
    }

private:
    void check(cudaError_t status, const char* call) const {
        if (status != cudaSuccess)
            throw Error(std::string("cuda ") + properties_.name + ": " + call + " failed (" +
                        cudaGetErrorString(status) + ")");
    }
    void allocation(cudaError_t status, const char* what) {
        if (status == cudaErrorMemoryAllocation) {
            cudaGetLastError();  // clear the sticky-free error so later calls work
            throw SizeSkipped(std::string("out of memory for ") + what);
        }
        check(status, what);
    }
    void* host_pointer(Memory host) const { return host == Memory::Pinned ? pinned_ : static_cast<void*>(pageable_); }

    template <typename Issue>
    Timed timed(Issue issue) {
        auto start = Clock::now();
        check(cudaEventRecord(start_, stream_), "cudaEventRecord");
        check(issue(), "the copy");
        check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
        check(cudaEventSynchronize(stop_), "cudaEventSynchronize");
        auto end = Clock::now();
        float milliseconds = 0;
        check(cudaEventElapsedTime(&milliseconds, start_, stop_), "cudaEventElapsedTime");
        return Timed{milliseconds * 1e-3, std::chrono::duration<double>(end - start).count()};
    }

    int ordinal_;
    cudaDeviceProp properties_{};
    cudaStream_t stream_ = nullptr;
    cudaEvent_t start_ = nullptr, stop_ = nullptr;
    size_t bytes_ = 0;
    std::byte* pageable_ = nullptr;
    void* buffer_a_ = nullptr;
    void* buffer_b_ = nullptr;
    void* pinned_ = nullptr;
};

}  // namespace

ApiResult measure_cuda(const Plan& plan) {
    ApiResult api{"cuda", "", {}};
    int count = 0;
    cudaError_t status = cudaGetDeviceCount(&count);
    if (status != cudaSuccess || count == 0) {
        api.unavailable_reason =
            std::string("no CUDA device (") + (status == cudaSuccess ? "0 devices" : cudaGetErrorString(status)) + ")";
        return api;
    }
    for (int ordinal = 0; ordinal < count; ++ordinal) {
        cudaDeviceProp properties{};
        cudaGetDeviceProperties(&properties, ordinal);
        if (!plan.wants("cuda", "CUDA", properties.name)) continue;
        try {
            CudaDevice device(ordinal);
            api.devices.push_back(sweep(device, plan));
        } catch (const Error& error) {
            DeviceResult failed{"cuda", properties.name, "CUDA"};
            failed.notes.push_back(std::string("device skipped: ") + error.what());
            api.devices.push_back(failed);
        }
    }
    if (api.devices.empty()) api.unavailable_reason = "no CUDA device matches the --device filters";
    return api;
}

}  // namespace prism::bandwidth
