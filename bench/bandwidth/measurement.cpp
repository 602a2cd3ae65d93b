#include "bench/bandwidth/measurement.h"

#include <algorithm>

namespace prism::bandwidth {

const char* direction_key(Direction direction) {
    switch (direction) {
        case Direction::HostToDevice: return "h2d";
        case Direction::DeviceToHost: return "d2h";
        case Direction::DeviceToDevice: return "d2d";
        case Direction::KernelCopy: return "kernel_copy";
    }
    return "?";
}

const char* direction_label(Direction direction) {
    switch (direction) {
        case Direction::HostToDevice: return "H2D";
        case Direction::DeviceToHost: return "D2H";
        case Direction::DeviceToDevice: return "D2D copy";
        case Direction::KernelCopy: return "D2D kernel";
    }
    return "?";
}

const char* memory_key(Memory memory) {
    switch (memory) {
        case Memory::Pageable: return "pageable";
        case Memory::Pinned: return "pinned";
        case Memory::Device: return "device";
    }
    return "?";
}

RateStats summarize(size_t bytes, std::vector<double> seconds) {
    std::sort(seconds.begin(), seconds.end());
    size_t n = seconds.size();
    double median = n % 2 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
    auto rate = [bytes](double s) { return static_cast<double>(bytes) / s * 1e-9; };
    // The fastest copy is the shortest time: min rate comes from the longest.
    return RateStats{rate(median), rate(seconds.back()), rate(seconds.front()), median};
}

}  // namespace prism::bandwidth
