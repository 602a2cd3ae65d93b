#include "backends/cuda/cuda_device.h"

#include <cuda_runtime.h>

#include <cctype>
#include <fstream>
#include <sstream>

#include "backends/cuda/cuda_launch.h"
#include "core/util/error.h"

namespace prism::cuda {
namespace {

std::string version_text(int version) {  // 13000 -> "13.0"
    return std::to_string(version / 1000) + "." + std::to_string(version % 1000 / 10);
}

}  // namespace

std::vector<DeviceDescription> list_devices(std::string& why) {
    std::vector<DeviceDescription> devices;
    int count = 0;
    cudaError_t status = cudaGetDeviceCount(&count);
    if (status != cudaSuccess) {
        why = std::string("cudaGetDeviceCount: ") + cudaGetErrorString(status);
        cudaGetLastError();  // clear it: later calls should report their own errors
        return devices;
    }
    if (count == 0) {
        why = "cudaGetDeviceCount: no CUDA-capable device is detected";
        return devices;
    }
    for (int i = 0; i < count; ++i) {
        cudaDeviceProp prop{};
        status = cudaGetDeviceProperties(&prop, i);
        if (status != cudaSuccess) {
            why = "cudaGetDeviceProperties(" + std::to_string(i) + "): " + cudaGetErrorString(status);
            cudaGetLastError();
            continue;
        }
        DeviceDescription d;
        d.index = i;
        d.name = prop.name;
        d.multiprocessors = prop.multiProcessorCount;
        d.total_memory = prop.totalGlobalMem;
        d.compute_major = prop.major;
        d.compute_minor = prop.minor;
        devices.push_back(d);
    }
    return devices;
}

std::string driver_version() {
    int version = 0;
    std::string cuda = cudaDriverGetVersion(&version) == cudaSuccess && version
                           ? "CUDA " + version_text(version) + " driver API"
                           : "no CUDA driver";
    // The kernel module's version (e.g. 580.159) is what people quote; NVML would be one more dependency.
    std::ifstream proc("/proc/driver/nvidia/version");
    std::string line;
    if (std::getline(proc, line)) {
        std::istringstream words(line);
        std::string word;
        while (words >> word)
            if (!word.empty() && std::isdigit(static_cast<unsigned char>(word[0])) &&
                word.find('.') != std::string::npos)
                return word + " (" + cuda + ")";
    }
    return cuda;
}

std::string runtime_version() {
    int version = 0;
    cudaRuntimeGetVersion(&version);
    return "CUDA " + version_text(version) + " runtime (static)";
}

DeviceContext::DeviceContext(const DeviceDescription& device) : device_(device) {
    check(cudaSetDevice(device_.index), "cudaSetDevice");
    cudaStream_t stream = nullptr;
    // Non-blocking: the legacy default stream (which other libraries may use) must not serialise with ours.
    check(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking), "cudaStreamCreate");
    stream_ = stream;
}

DeviceContext::~DeviceContext() {
    bind();
    if (stream_) cudaStreamSynchronize(static_cast<cudaStream_t>(stream_));
    for (void* event : events_) cudaEventDestroy(static_cast<cudaEvent_t>(event));
    if (stream_) cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
}

void DeviceContext::bind() const { cudaSetDevice(device_.index); }

void DeviceContext::check(int status, const std::string& what) const {
    if (status == cudaSuccess) return;
    cudaError_t error = static_cast<cudaError_t>(status);
    cudaGetLastError();  // clear non-sticky errors so the next call reports its own
    throw Error("cuda: " + what + " on " + device_.name + ": " + cudaGetErrorString(error) + " (" +
                cudaGetErrorName(error) + ")");
}

size_t DeviceContext::free_memory() {
    bind();
    size_t free = 0, total = 0;
    check(cudaMemGetInfo(&free, &total), "cudaMemGetInfo");
    return free;
}

void* DeviceContext::allocate(size_t bytes, const char* what) {
    bind();
    void* pointer = nullptr;
    check(cudaMalloc(&pointer, bytes),
          std::string("cudaMalloc of buffer '") + what + "' (" + std::to_string(bytes) + " bytes)");
    return pointer;
}

void DeviceContext::release(void* pointer) {
    if (!pointer) return;
    bind();
    check(cudaFree(pointer), "cudaFree");  // waits for the device: no launch still uses it
}

void* DeviceContext::allocate_host(size_t bytes, const char* what) {
    bind();
    void* pointer = nullptr;
    check(cudaMallocHost(&pointer, bytes),
          std::string("cudaMallocHost for '") + what + "' (" + std::to_string(bytes) + " bytes)");
    return pointer;
}

void DeviceContext::release_host(void* pointer) {
    if (!pointer) return;
    bind();
    check(cudaFreeHost(pointer), "cudaFreeHost");
}

void DeviceContext::copy_to_device(void* device_pointer, const void* host, size_t bytes) {
    if (!bytes) return;
    bind();
    // From pageable memory the runtime copies `host` into a staging buffer before returning, so the caller may
    // reuse it at once (CUDA runtime API, "API synchronization behavior").
    check(cudaMemcpyAsync(device_pointer, host, bytes, cudaMemcpyHostToDevice, static_cast<cudaStream_t>(stream_)),
          "cudaMemcpyAsync (host to device)");
}

void DeviceContext::copy_to_host(void* host, const void* device_pointer, size_t bytes) {
    bind();
    if (bytes)
        check(cudaMemcpyAsync(host, device_pointer, bytes, cudaMemcpyDeviceToHost, static_cast<cudaStream_t>(stream_)),
              "cudaMemcpyAsync (device to host)");
    check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream_)), "cudaStreamSynchronize (read)");
}

void DeviceContext::fill_zero(void* device_pointer, size_t bytes) {
    if (!bytes) return;
    bind();
    check(cudaMemsetAsync(device_pointer, 0, bytes, static_cast<cudaStream_t>(stream_)), "cudaMemsetAsync");
}

void DeviceContext::launch(unsigned stage, const char* stage_name, void* const* pointers, unsigned depth,
                           unsigned blocks, unsigned threads) {
    bind();
    while (events_.size() < 2 * (launches_ + 1)) {
        cudaEvent_t event = nullptr;
        check(cudaEventCreate(&event), "cudaEventCreate");
        events_.push_back(event);
    }
    auto stream = static_cast<cudaStream_t>(stream_);
    check(cudaEventRecord(static_cast<cudaEvent_t>(events_[2 * launches_]), stream), "cudaEventRecord");
    check(launch_stage(stage, pointers, depth, blocks, threads, stream_),
          std::string("launching stage '") + stage_name + "' (" + std::to_string(blocks) + "x" +
              std::to_string(threads) + ")");
    check(cudaEventRecord(static_cast<cudaEvent_t>(events_[2 * launches_ + 1]), stream), "cudaEventRecord");
    ++launches_;
}

std::vector<double> DeviceContext::synchronize_and_collect_ms() {
    bind();
    size_t launches = launches_;
    launches_ = 0;  // even if the sync throws, the next frame starts a fresh list
    // Errors inside a kernel (an illegal address, ...) surface here.
    check(cudaStreamSynchronize(static_cast<cudaStream_t>(stream_)), "cudaStreamSynchronize (finish)");
    std::vector<double> ms(launches);
    for (size_t i = 0; i < launches; ++i) {
        float elapsed = 0.0f;
        check(cudaEventElapsedTime(&elapsed, static_cast<cudaEvent_t>(events_[2 * i]),
                                   static_cast<cudaEvent_t>(events_[2 * i + 1])),
              "cudaEventElapsedTime");
        ms[i] = elapsed;
    }
    return ms;
}

}  // namespace prism::cuda
