// Per-frame timings of `prism view` and their summary: printed when the viewer exits, and written as JSON with
// --stats F.json for bench/view_gpu.sh. Medians, after a few warm-up frames (first launches, buffer set-up).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace prism::viewer {

struct FrameTiming {
    double render_ms = 0.0;    // RenderEngine::render: the frame on the device, plus its read-back for a host copy
    double display_ms = 0.0;   // display update (device copy or texture upload) + draw, until GL has done them
    double present_ms = 0.0;   // the buffer swap (under Xvfb: a copy of the window into the X server)
    double frame_ms = 0.0;     // from the previous frame's present to this one's: what fps is made of
};

class FrameTimings {
public:
    void add(const FrameTiming& timing) { frames_.push_back(timing); }
    size_t frames() const { return frames_.size(); }
    // The first min(5, frames/4) frames are left out of the medians.
    size_t warmup() const;

    struct Summary {
        size_t frames = 0, measured = 0;
        double render_ms = 0.0, display_ms = 0.0, present_ms = 0.0, frame_ms = 0.0;   // medians
        double fps = 0.0;                                             // 1000 / median frame_ms
    };
    Summary summary() const;
    // "timing: 95 frames after 5 warm-up, median render 12.31 ms, display 0.42 ms, present 0.05 ms, frame 12.80 ms
    // (78.1 fps)"
    std::string summary_line() const;
    // The summary and the per-frame values (all frames, warm-up included).
    nlohmann::json json() const;

private:
    std::vector<FrameTiming> frames_;
};

}  // namespace prism::viewer
