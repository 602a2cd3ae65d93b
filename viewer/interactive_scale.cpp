#include "viewer/interactive_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/util/error.h"

namespace prism::viewer {
namespace {

constexpr double kStep = 1.0 / 8.0;  // coarse steps: each new scale re-creates the display's buffers

double quantize(double scale) { return std::clamp(std::round(scale / kStep) * kStep, kStep, 1.0); }

}  // namespace

InteractiveScale::InteractiveScale(const std::string& setting, double target_fps) : target_fps_(target_fps) {
    if (!(target_fps > 0.0 && target_fps <= 1000.0))
        throw Error("view: --target-fps " + std::to_string(target_fps) + " is not in (0, 1000]");
    if (setting == "auto") return;
    char* end = nullptr;
    double value = std::strtod(setting.c_str(), &end);
    if (setting.empty() || *end != '\0' || !(value > 0.0 && value <= 1.0))
        throw Error("view: --interactive-scale '" + setting + "' is not auto or a fraction in (0, 1]");
    automatic_ = false;
    scale_ = value;
}

void InteractiveScale::record(uint32_t width, uint32_t height, double render_ms) {
    double pixels = double(width) * double(height);
    full_pixels_ = std::max(full_pixels_, pixels);
    if (!automatic_ || pixels <= 0.0 || render_ms <= 0.0) return;
    // Render time grows with the pixel count: the per-axis scale that would have met the target is
    // sqrt(target / measured) of this frame's.
    double target_ms = 1000.0 / target_fps_;
    double this_scale = std::sqrt(pixels / full_pixels_);
    // A frame between half the target and the target keeps the scale: render times are noisy, and a frame's
    // fixed costs (launches, the queue reads) do not shrink with its size, so chasing every frame only drifts.
    if (render_ms <= target_ms && render_ms >= 0.5 * target_ms && this_scale == scale_) return;
    scale_ = quantize(this_scale * std::sqrt(target_ms / render_ms));
}

uint32_t InteractiveScale::scaled(uint32_t full, double scale) {
    auto pixels = uint32_t(std::lround(double(full) * scale));
    return std::min(full, std::max(pixels, 8u));
}

}  // namespace prism::viewer
