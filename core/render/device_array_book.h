// The bookkeeping every backend keeps for its device arrays (core/render/backend.h): each array's size, the range check
// of reads and writes, and the memory budget (the device's memory, or PRISM_DEVICE_MEMORY_LIMIT where smaller), so that
// every API applies the same rules and words its errors alike. A backend keeps what is particular to its API (CUDA's
// free-memory query, OpenCL's and Vulkan's largest single allocation) beside it.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "core/render/backend.h"

namespace prism {

// "12.5 MiB".
std::string mib_text(size_t bytes);

class DeviceArrayBook {
public:
    // `api` begins every message ("cuda"); `device` names the device in them. With `device_memory` the arrays
    // together may take that much, or PRISM_DEVICE_MEMORY_LIMIT when it is set and smaller (read here: a bad value
    // throws prism::Error naming the variable); without, the book keeps sizes only (the cpu backend's host memory
    // has its own guard, core/render/host_memory.h).
    DeviceArrayBook(std::string api, std::string device, std::optional<size_t> device_memory);

    // Throws prism::Error naming the array, its size, the total it would bring and the budget (and the variable,
    // when the budget is PRISM_DEVICE_MEMORY_LIMIT) when `array`, (re)allocated to `device_bytes` (its size with
    // the backend's padding), would not fit beside the others. Checks only: call `record` once it is allocated.
    void check_fits(DeviceArray array, size_t bytes, size_t device_bytes) const;
    void record(DeviceArray array, size_t bytes, size_t device_bytes);
    void forget(DeviceArray array);  // released

    // Throws prism::Error "<api>: access past the end of array '<name>' (<offset>+<bytes> of <size> bytes)" unless
    // [offset, offset + bytes) lies inside the array as allocated.
    void check_range(DeviceArray array, size_t bytes, size_t offset) const;

    size_t size(DeviceArray array) const { return sizes_[size_t(array)]; }
    bool allocated(DeviceArray array) const { return allocated_[size_t(array)]; }
    size_t device_bytes(DeviceArray array) const { return device_bytes_[size_t(array)]; }
    size_t total_device_bytes() const;
    // Bytes the arrays may take together (SIZE_MAX without a budget), and what set it, for messages.
    size_t budget() const { return budget_; }
    const std::string& budget_note() const { return budget_note_; }

private:
    std::string api_;
    std::array<size_t, device_array_count> sizes_{};
    std::array<size_t, device_array_count> device_bytes_{};
    std::array<bool, device_array_count> allocated_{};
    size_t budget_ = SIZE_MAX;
    std::string budget_note_;  // " of memory of <device>" or " allowed on <device> (PRISM_DEVICE_MEMORY_LIMIT=N)"
};

}  // namespace prism
