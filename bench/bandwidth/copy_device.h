// The one interface each API implements (cuda_bandwidth.cu, opencl_bandwidth.cpp, vulkan_bandwidth.cpp), so the
// sweep order, warm-up, repeats, data checks and skip notes are written once (sweep.cpp).
//
// For one size the sweep calls allocate(), then the timed copies in a fixed order, then release(). Buffer A is
// the transfer target and copy source, B the copy destination; the host side is either the caller's pageable
// buffer or the API's own pinned/staging memory.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bandwidth/measurement.h"

namespace prism::bandwidth {

// A size (or one kind of copy at that size) that does not fit this device: a note, not an error.
class SizeSkipped : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class CopyDevice {
public:
    virtual ~CopyDevice() = default;
    // Name, driver, versions, PCI address, memory spec, details; filled before and refined after the sweep.
    virtual DeviceResult describe() const = 0;

    // Why `bytes` cannot be measured at all (device memory, largest buffer, heap size), or empty.
    virtual std::string cannot_fit(size_t bytes) const = 0;
    // Why the kernel copy cannot run at `bytes` (e.g. Vulkan maxStorageBufferRange), or empty.
    virtual std::string kernel_cannot_fit(size_t bytes) const = 0;

    // Device buffers A and B and the pinned/staging host memory, for `bytes`. `pageable` (bytes long) is
    // ordinary host memory owned by the caller. Throws SizeSkipped when an allocation fails.
    virtual void allocate(size_t bytes, std::byte* pageable) = 0;
    virtual void release() = 0;
    // The API's pinned host memory, `bytes` long: the source of pinned uploads and the destination of pinned
    // downloads. The same memory on CUDA and OpenCL; on Vulkan two mapped staging buffers (the readback one
    // host-cached).
    virtual std::byte* pinned_upload() = 0;
    virtual std::byte* pinned_download() = 0;

    // The queues the copy commands (upload, download, copy_buffer) can run on, each measured in turn; {""} where
    // the API has no choice of queue.
    virtual std::vector<std::string> copy_queues() const { return {""}; }
    // Runs the copy commands on `queue`, one of copy_queues(), from now on.
    virtual void use_copy_queue(const std::string& /*queue*/) {}

    virtual Timed upload(Memory host) = 0;    // host -> A
    virtual Timed download(Memory host) = 0;  // A -> host
    virtual Timed copy_buffer() = 0;          // A -> B with the API's copy command
    virtual Timed copy_kernel() = 0;          // A -> B with kernels/bandwidth_copy.h
    // Untimed helpers for checking data: zero B; read B into the pageable buffer.
    virtual void clear_destination() = 0;
    virtual void read_destination() = 0;
};

}  // namespace prism::bandwidth
