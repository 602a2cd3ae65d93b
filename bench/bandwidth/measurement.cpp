#include "bench/bandwidth/measurement.h"

#include <algorithm>

namespace prism::bandwidth {

namespace {

// A direction's JSON key and its label in tables and plots, in one switch so that a new direction gets both.
struct DirectionNames {
    const char* key;
    const char* label;
};

DirectionNames direction_names(Direction direction) {
    switch (direction) {
        case Direction::HostToDevice: return {"h2d", "H2D"};
        case Direction::DeviceToHost: return {"d2h", "D2H"};
        case Direction::DeviceToDevice: return {"d2d", "D2D copy"};
        case Direction::KernelCopy: return {"kernel_copy", "D2D kernel"};
    }
    return {"?", "?"};
}

}  // namespace

const char* direction_key(Direction direction) { return direction_names(direction).key; }

const char* direction_label(Direction direction) { return direction_names(direction).label; }

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
