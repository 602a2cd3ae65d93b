// Per-frame timings of `prism view` and their summary: printed when the viewer exits, and written as JSON with
// --stats F.json for bench/view_gpu.sh. Medians, after a few warm-up frames (first launches, buffer set-up).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace prism::viewer {

struct FrameTiming {
    double render_ms = 0.0;        // RenderEngine::render: the frame on the device, plus its read-back for a host copy
    double display_ms = 0.0;       // host time of the display update (texture upload from host memory; for interop
                                   // only GL's side: the frame copied itself) + draw, as issued: GL runs them
                                   // asynchronously
    double present_ms = 0.0;       // the buffer swap (offscreen: glFlush)
    double frame_ms = 0.0;         // from the previous frame's present to this one's: what fps is made of
    double gpu_display_ms = -1.0;  // GL's GPU time for the display commands (GL_TIME_ELAPSED); < 0: not known
    // --alternate-display: whether this frame was shown (its copy, upload, draw and swap done) or only rendered,
    // and whether it is the first of its block (left out of the A/B medians: it carries what the block before it
    // left running on the GPU).
    enum class Block { None, Shown, Hidden };
    Block block = Block::None;
    bool first_of_block = false;
};

class FrameTimings {
public:
    void add(const FrameTiming& timing) { frames_.push_back(timing); }
    // A GPU time read back after the frame was added (viewer/gl_timer.h).
    void set_gpu_display(size_t frame, double ms) {
        if (frame < frames_.size()) frames_[frame].gpu_display_ms = ms;
    }
    size_t frames() const { return frames_.size(); }
    // The first min(5, frames/4) frames are left out of the medians.
    size_t warmup() const;

    struct Summary {
        size_t frames = 0, measured = 0;
        // Medians; display and present (and the GPU time) over the frames shown only (see --alternate-display).
        double render_ms = 0.0, display_ms = 0.0, present_ms = 0.0, frame_ms = 0.0;
        double gpu_display_ms = -1.0;   // median of the frames whose GPU time is known; < 0: none
        double beyond_render_ms = 0.0;  // median of frame_ms - render_ms: what the viewer adds to each frame's time
        double fps = 0.0;               // 1000 / median frame_ms
        // --alternate-display: median frame and render time of the shown and of the hidden frames (after warm-up,
        // first frames of blocks left out), and what showing adds to a frame: shown - hidden, within one run, so
        // the render's drift between runs stays out of it. Zero counts: no A/B.
        size_t shown = 0, hidden = 0;
        double shown_frame_ms = 0.0, hidden_frame_ms = 0.0, shown_render_ms = 0.0, hidden_render_ms = 0.0;
        double added_ms = 0.0;
    };
    Summary summary() const;
    // "timing: 95 frames after 5 warm-up, median render 12.31 ms, display 0.42 ms (GL on the GPU 0.03 ms), present
    // 0.05 ms, frame 12.80 ms (78.1 fps)"
    std::string summary_line() const;
    // The summary and the per-frame values (all frames, warm-up included).
    nlohmann::json json() const;

private:
    std::vector<FrameTiming> frames_;
};

}  // namespace prism::viewer
