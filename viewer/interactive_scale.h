// --interactive-scale: while the camera or the scene moves, frames are rendered at a fraction of the window's
// resolution (and shown stretched over it) so that the preview keeps up with the input; once nothing moves, one
// frame at full resolution follows. "auto" picks the fraction from the measured render times so that a moving
// frame takes about 1/--target-fps; a number fixes it.
#pragma once

#include <cstdint>
#include <string>

namespace prism::viewer {

class InteractiveScale {
public:
    // `setting`: "auto" or a fraction in (0, 1] ("1": always full resolution). Throws prism::Error naming
    // --interactive-scale or --target-fps on a bad value.
    InteractiveScale(const std::string& setting, double target_fps);

    // A frame of width x height pixels took `render_ms` to render: the next moving frame's scale follows it.
    void record(uint32_t width, uint32_t height, double render_ms);
    // The fraction of the full resolution (per axis) for frames while moving: a multiple of 1/8, at least 1/8.
    double moving_scale() const { return scale_; }
    bool automatic() const { return automatic_; }
    double target_fps() const { return target_fps_; }

    // full * scale, at least 8 pixels (and never more than full).
    static uint32_t scaled(uint32_t full, double scale);

private:
    bool automatic_ = true;
    double target_fps_;
    double scale_ = 1.0;
    double full_pixels_ = 0.0;  // the largest frame recorded: the window's resolution
};

}  // namespace prism::viewer
