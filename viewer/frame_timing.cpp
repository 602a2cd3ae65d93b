#include "viewer/frame_timing.h"

#include <algorithm>
#include <cstdio>

#include "core/util/median.h"

namespace prism::viewer {

size_t FrameTimings::warmup() const { return std::min<size_t>(5, frames_.size() / 4); }

FrameTimings::Summary FrameTimings::summary() const {
    Summary s;
    s.frames = frames_.size();
    std::vector<double> render, display, present, frame, gpu_display, beyond_render;
    for (size_t i = warmup(); i < frames_.size(); ++i) {
        beyond_render.push_back(frames_[i].frame_ms - frames_[i].render_ms);
        render.push_back(frames_[i].render_ms);
        frame.push_back(frames_[i].frame_ms);
        if (frames_[i].block == FrameTiming::Block::Hidden) continue;  // the display's medians: shown frames only
        if (frames_[i].gpu_display_ms >= 0.0) gpu_display.push_back(frames_[i].gpu_display_ms);
        display.push_back(frames_[i].display_ms);
        present.push_back(frames_[i].present_ms);
    }
    s.measured = frame.size();
    s.render_ms = median(render);
    s.display_ms = median(display);
    s.present_ms = median(present);
    s.frame_ms = median(frame);
    if (!gpu_display.empty()) s.gpu_display_ms = median(gpu_display);
    s.beyond_render_ms = median(beyond_render);
    s.fps = s.frame_ms > 0.0 ? 1000.0 / s.frame_ms : 0.0;

    std::vector<double> shown_frame, hidden_frame, shown_render, hidden_render;
    for (size_t i = warmup(); i < frames_.size(); ++i) {
        const FrameTiming& t = frames_[i];
        if (t.first_of_block || t.block == FrameTiming::Block::None) continue;
        bool shown = t.block == FrameTiming::Block::Shown;
        (shown ? shown_frame : hidden_frame).push_back(t.frame_ms);
        (shown ? shown_render : hidden_render).push_back(t.render_ms);
    }
    s.shown = shown_frame.size();
    s.hidden = hidden_frame.size();
    if (s.shown != 0 && s.hidden != 0) {
        s.shown_frame_ms = median(shown_frame);
        s.hidden_frame_ms = median(hidden_frame);
        s.shown_render_ms = median(shown_render);
        s.hidden_render_ms = median(hidden_render);
        s.added_ms = s.shown_frame_ms - s.hidden_frame_ms;
    }
    return s;
}

std::string FrameTimings::summary_line() const {
    Summary s = summary();
    char gpu[48] = "";
    if (s.gpu_display_ms >= 0.0) std::snprintf(gpu, sizeof gpu, " (GL on the GPU %.3f ms)", s.gpu_display_ms);
    char line[320];
    std::snprintf(line, sizeof line,
                  "timing: %zu frames after %zu warm-up, median render %.2f ms, display %.2f ms%s, present %.2f ms, "
                  "frame %.2f ms (%.1f fps)",
                  s.measured, warmup(), s.render_ms, s.display_ms, gpu, s.present_ms, s.frame_ms, s.fps);
    if (s.shown == 0 || s.hidden == 0) return line;
    char ab[200];
    std::snprintf(ab, sizeof ab,
                  "; alternating: shown %.3f ms (%zu frames), not shown %.3f ms (%zu), showing adds %.3f ms",
                  s.shown_frame_ms, s.shown, s.hidden_frame_ms, s.hidden, s.added_ms);
    return std::string(line) + ab;
}

nlohmann::json FrameTimings::json() const {
    Summary s = summary();
    nlohmann::json render = nlohmann::json::array(), display = nlohmann::json::array(),
                   present = nlohmann::json::array(), frame = nlohmann::json::array(),
                   gpu_display = nlohmann::json::array();
    for (const FrameTiming& t : frames_) {
        render.push_back(t.render_ms);
        gpu_display.push_back(t.gpu_display_ms >= 0.0 ? nlohmann::json(t.gpu_display_ms) : nlohmann::json());
        display.push_back(t.display_ms);
        present.push_back(t.present_ms);
        frame.push_back(t.frame_ms);
    }
    nlohmann::json shown = nlohmann::json::array();
    for (const FrameTiming& t : frames_)
        shown.push_back(t.block == FrameTiming::Block::None ? nlohmann::json()
                                                            : nlohmann::json(t.block == FrameTiming::Block::Shown));
    nlohmann::json alternating;  // null without --alternate-display
    if (s.shown != 0 && s.hidden != 0)
        alternating = {{"shown_frames", s.shown},
                       {"hidden_frames", s.hidden},
                       {"median_frame_ms_shown", s.shown_frame_ms},
                       {"median_frame_ms_hidden", s.hidden_frame_ms},
                       {"median_render_ms_shown", s.shown_render_ms},
                       {"median_render_ms_hidden", s.hidden_render_ms},
                       {"added_ms", s.added_ms}};
    return {{"frames", s.frames},
            {"warmup_frames", warmup()},
            {"measured_frames", s.measured},
            {"median_render_ms", s.render_ms},
            {"median_display_ms", s.display_ms},
            {"median_present_ms", s.present_ms},
            {"median_frame_ms", s.frame_ms},
            {"median_beyond_render_ms", s.beyond_render_ms},
            {"median_gpu_display_ms", s.gpu_display_ms >= 0.0 ? nlohmann::json(s.gpu_display_ms) : nlohmann::json()},
            {"fps", s.fps},
            {"alternating", alternating},
            {"per_frame",
             {{"render_ms", render},
              {"display_ms", display},
              {"present_ms", present},
              {"frame_ms", frame},
              {"gpu_display_ms", gpu_display},
              {"shown", shown}}}};
}

}  // namespace prism::viewer
