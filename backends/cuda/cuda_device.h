// The CUDA runtime behind a header without CUDA types. The CUDA headers define float4 & co. globally, and so
// does kernels/compat/cpu.h, which the Backend interface includes: cuda_device.cpp is the only host file that
// includes <cuda_runtime.h>, and it includes nothing of kernels/.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace prism::cuda {

struct DeviceDescription {
    int index = 0;
    std::string name;
    int multiprocessors = 0;
    size_t total_memory = 0;
    int compute_major = 0, compute_minor = 0;
};

// The CUDA devices of this machine. Never throws: on failure returns none and sets `why` to the one-line cause,
// e.g. "cudaGetDeviceCount: CUDA driver version is insufficient for CUDA runtime version".
std::vector<DeviceDescription> list_devices(std::string& why);
// "580.159 (CUDA 13.0 driver API)" where the driver says so; "runtime 13.0" style for the runtime.
std::string driver_version();
std::string runtime_version();

// One device and one in-order stream. Every failing call throws prism::Error "cuda: <what> on <device>: <cause>".
class DeviceContext {
public:
    explicit DeviceContext(const DeviceDescription& device);
    ~DeviceContext();
    DeviceContext(const DeviceContext&) = delete;
    DeviceContext& operator=(const DeviceContext&) = delete;

    const DeviceDescription& device() const { return device_; }

    size_t free_memory();
    void* allocate(size_t bytes, const char* what);
    void release(void* pointer);
    void* allocate_host(size_t bytes, const char* what);  // page-locked (cudaMallocHost)
    void release_host(void* pointer);
    void copy_to_device(void* device_pointer, const void* host, size_t bytes);  // asynchronous on the stream
    void copy_to_host(void* host, const void* device_pointer, size_t bytes);    // waits for it (and all before)
    void fill_zero(void* device_pointer, size_t bytes);                         // asynchronous on the stream

    // Launch of a stage between two timing events; `pointers` as in cuda_launch.h.
    void launch(unsigned stage, const char* stage_name, void* const* pointers, unsigned depth, unsigned blocks,
                unsigned threads);
    // Waits for the stream and returns the device time of each launch since the last call, in launch order.
    std::vector<double> synchronize_and_collect_ms();

    // For code next to this one that calls the runtime itself (cuda_gl_interop.cpp): the stream (a cudaStream_t),
    // making this device current, and the error check that throws the message above.
    void* stream() const { return stream_; }
    void bind() const;
    void check(int status, const std::string& what) const;

private:
    DeviceDescription device_;
    void* stream_ = nullptr;
    std::vector<void*> events_;  // pool: launch i uses events 2i and 2i+1
    size_t launches_ = 0;        // launches since the last collection
};

}  // namespace prism::cuda
