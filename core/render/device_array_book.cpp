#include "core/render/device_array_book.h"

#include <cstdint>
#include <cstdio>

#include "core/render/device_memory_limit.h"
#include "core/util/error.h"

namespace prism {

std::string mib_text(size_t bytes) {
    char text[64];
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
    return text;
}

DeviceArrayBook::DeviceArrayBook(std::string api, std::string device, std::optional<size_t> device_memory)
    : api_(std::move(api)) {
    if (!device_memory) return;
    budget_ = *device_memory;
    budget_note_ = " of memory of " + device;
    std::optional<size_t> limit = device_memory_limit();
    if (limit && *limit < budget_) {
        budget_ = *limit;
        budget_note_ = " allowed on " + device + " (PRISM_DEVICE_MEMORY_LIMIT=" + std::to_string(*limit) + ")";
    }
}

size_t DeviceArrayBook::total_device_bytes() const {
    size_t total = 0;
    for (size_t bytes : device_bytes_) total += bytes;
    return total;
}

void DeviceArrayBook::check_fits(DeviceArray array, size_t bytes, size_t device_bytes) const {
    if (budget_ == SIZE_MAX) return;
    // The array's old allocation is released first, so it does not count.
    const size_t others = total_device_bytes() - device_bytes_[size_t(array)];
    if (device_bytes > budget_ || others > budget_ - device_bytes)
        throw Error(api_ + ": buffer '" + device_array_name(array) + "' needs " + mib_text(bytes) +
                    ", bringing the total to " + mib_text(others + device_bytes) + ", above the " + mib_text(budget_) +
                    budget_note_);
}

void DeviceArrayBook::record(DeviceArray array, size_t bytes, size_t device_bytes) {
    sizes_[size_t(array)] = bytes;
    device_bytes_[size_t(array)] = device_bytes;
    allocated_[size_t(array)] = true;
}

void DeviceArrayBook::forget(DeviceArray array) {
    sizes_[size_t(array)] = 0;
    device_bytes_[size_t(array)] = 0;
    allocated_[size_t(array)] = false;
}

void DeviceArrayBook::check_range(DeviceArray array, size_t bytes, size_t offset) const {
    const size_t size = sizes_[size_t(array)];
    if (!allocated_[size_t(array)] || offset > size || bytes > size - offset)
        throw Error(api_ + ": access past the end of array '" + device_array_name(array) + "' (" +
                    std::to_string(offset) + "+" + std::to_string(bytes) + " of " + std::to_string(size) + " bytes)");
}

}  // namespace prism
