// The Figure 8-1 view of the results: per device, API, direction and memory kind, the peak (best median over
// the swept sizes), its share of the best API on the same device, and its share of the link or memory spec.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bench/bandwidth/measurement.h"

namespace prism::bandwidth {

struct SummaryRow {
    const DeviceResult* device = nullptr;
    const Measurement* peak = nullptr;  // the size with the best median (device timer, else wall) on one queue
    double percent_of_best = 0;         // of the best API on the same device (by name) for this kind of copy
    std::optional<double> percent_of_spec;
    std::string spec;  // "PCIe 32.0 GT/s x16 (63.0 GB/s)" or "memory 3352 GB/s r+w"
};

// Rows in the order of `apis`, then device, then H2D pageable/pinned, D2H pageable/pinned, D2D copy, kernel; a kind
// measured on several queues (Vulkan) has a row per queue, each compared with the best of every API and queue.
// Spec figures are properties of the hardware: one reported through any API serves every API on that device.
std::vector<SummaryRow> summarize_peaks(const std::vector<ApiResult>& apis);

// The rate a row is compared by: bytes copied per second, or read+write traffic for device-to-device copies when
// comparing with a memory spec.
double read_write_gbps(const Measurement& measurement, double gbps);

}  // namespace prism::bandwidth
