// What `prism bandwidth` measures and records: one Measurement per (device, direction, memory kind, size).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace prism::bandwidth {

enum class Direction { HostToDevice, DeviceToHost, DeviceToDevice, KernelCopy };
enum class Memory { Pageable, Pinned, Device };

const char* direction_key(Direction direction);    // "h2d", "d2h", "d2d", "kernel_copy" (JSON)
const char* direction_label(Direction direction);  // "H2D", "D2H", "D2D copy", "D2D kernel" (table, plot)
const char* memory_key(Memory memory);             // "pageable", "pinned", "device"

// Device-to-device copies read and write every byte: CUDA's bandwidthTest reports that read+write traffic,
// nvbandwidth reports bytes copied. We report bytes copied and give read+write beside it.
inline bool counts_read_and_write(Direction direction) {
    return direction == Direction::DeviceToDevice || direction == Direction::KernelCopy;
}

// One timed copy. device_seconds is empty where the API has no device timer for this kind of copy.
struct Timed {
    std::optional<double> device_seconds;
    double wall_seconds = 0;
};

// Summary of N repeats of one copy, in GB/s (1e9 bytes per second) of bytes copied.
struct RateStats {
    double median_gbps = 0;
    double min_gbps = 0;
    double max_gbps = 0;
    double median_seconds = 0;
};

struct Measurement {
    Direction direction = Direction::HostToDevice;
    Memory memory = Memory::Pageable;
    size_t bytes = 0;
    // The queue a copy command ran on where the API lets the program choose (Vulkan: "compute" or "transfer"), so
    // users see which to use; empty for CUDA and OpenCL, whose drivers pick the engine, and for the copy kernel.
    std::string queue;
    std::optional<RateStats> device_timer;  // cudaEvent / OpenCL profiling / vkCmdWriteTimestamp
    RateStats wall;                         // host steady clock around submit + wait
    // The figure the tables compare: the device timer where there is one, else wall time.
    double primary_gbps() const { return device_timer ? device_timer->median_gbps : wall.median_gbps; }
};

// Peak rates the device (or its driver) reports, for "% of spec".
struct LinkInfo {
    std::string description;  // e.g. "PCIe 32.0 GT/s x16"
    double gbps = 0;          // per direction, after line encoding
};

struct DeviceResult {
    std::string api;           // "cuda", "opencl", "vulkan"
    std::string device;        // device name as the API reports it
    std::string platform;      // OpenCL platform; Vulkan driver name; CUDA: "CUDA"
    std::string driver;        // driver version
    std::string api_version;   // e.g. "CUDA runtime 13.0, driver API 13.0", "OpenCL 1.2 PoCL ...", "Vulkan 1.3.239"
    std::string pci_address;   // "dddd:bb:dd.f" where the API reports it
    size_t device_memory = 0;  // bytes
    std::optional<double> memory_spec_gbps;  // bus width x memory clock x 2 (CUDA), read+write
    std::optional<LinkInfo> link;            // from sysfs for the PCI address, read right after transfers
    std::vector<std::string> details;        // how this API's copies are done (queues, memory types)
    std::vector<std::string> notes;          // sizes or kinds skipped, and why
    std::vector<Measurement> measurements;
};

// One API's outcome: its devices, or why it could not be measured.
struct ApiResult {
    std::string api;
    std::string unavailable_reason;  // empty when the API ran
    std::vector<DeviceResult> devices;
};

// Median/min/max rate of `bytes` over the samples (seconds); samples must be non-empty.
RateStats summarize(size_t bytes, std::vector<double> seconds);

}  // namespace prism::bandwidth
