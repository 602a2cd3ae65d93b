#include "core/util/load_progress.h"

#include <algorithm>

namespace prism {
namespace {

struct ThreadProgress {
    const LoadProgressCallback* callback = nullptr;
    double offset = 0.0, scale = 1.0;
};

thread_local ThreadProgress current;

}  // namespace

LoadProgressScope::LoadProgressScope(LoadProgressCallback callback)
    : callback_(std::move(callback)), previous_(current.callback) {
    current.callback = &callback_;
}

LoadProgressScope::~LoadProgressScope() { current.callback = previous_; }

LoadProgressShare::LoadProgressShare(double begin, double end)
    : previous_offset_(current.offset), previous_scale_(current.scale) {
    current.offset += current.scale * std::clamp(begin, 0.0, 1.0);
    current.scale *= std::max(0.0, std::clamp(end, 0.0, 1.0) - std::clamp(begin, 0.0, 1.0));
}

LoadProgressShare::~LoadProgressShare() {
    current.offset = previous_offset_;
    current.scale = previous_scale_;
}

void report_load_progress(double fraction) {
    if (current.callback && *current.callback)
        (*current.callback)(current.offset + current.scale * std::clamp(fraction, 0.0, 1.0));
}

}  // namespace prism
