#include "apps/frame_report.h"

#include <cstdio>

namespace prism::app {

double StageTotals::total() const {
    double sum = 0.0;
    for (double ms : by_stage) sum += ms;
    return sum;
}

StageTotals stage_totals(const FrameStats& stats) {
    StageTotals totals;
    for (const StageTiming& t : stats.stages) totals.by_stage[size_t(t.stage)] += t.milliseconds;
    return totals;
}

static std::string millions(uint64_t n) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2fM", double(n) / 1e6);
    return text;
}

std::string frame_summary(const FrameResult& frame, const RenderSettings& settings) {
    const FrameStats& s = frame.stats;
    uint64_t primary = s.rays_per_depth.empty() ? 0 : s.rays_per_depth[0];
    uint64_t secondary = 0, shadow = 0;
    for (size_t d = 1; d < s.rays_per_depth.size(); ++d) secondary += s.rays_per_depth[d];
    for (uint32_t n : s.shadow_rays_per_depth) shadow += n;
    char line[512];
    std::snprintf(line, sizeof line,
                  "  %ux%u, depth %u: frame %.2f ms (%.2f fps), %s rays (primary %s, secondary %s, shadow %s), "
                  "%.1f Mrays/s\n",
                  frame.width, frame.height, settings.max_depth, s.frame_ms, 1000.0 / s.frame_ms,
                  millions(s.total_rays()).c_str(), millions(primary).c_str(), millions(secondary).c_str(),
                  millions(shadow).c_str(), double(s.total_rays()) / (s.frame_ms * 1e3));
    std::string out = line;
    if (!s.stages.empty()) {
        StageTotals totals = stage_totals(s);
        out += "  stages:";
        for (size_t i = 0; i < stage_count; ++i) {
            std::snprintf(line, sizeof line, " %s %.2f ms%s", stage_name(Stage(i)), totals.by_stage[i],
                          i + 1 < stage_count ? "," : "\n");
            out += line;
        }
    }
    if (s.frame_ms > 0.0 && (s.enqueue_ms > 0.0 || s.readback_ms > 0.0)) {
        std::snprintf(line, sizeof line, "  host: enqueue %.2f ms, wait for device %.2f ms, read back %.2f ms\n",
                      s.enqueue_ms, s.device_wait_ms, s.readback_ms);
        out += line;
    }
    return out;
}

nlohmann::json frame_json(const FrameResult& frame, const RenderSettings& settings, const BackendInfo& info) {
    const FrameStats& s = frame.stats;
    nlohmann::json stages = nlohmann::json::array();
    for (const StageTiming& t : s.stages)
        stages.push_back({{"stage", stage_name(t.stage)}, {"depth", t.depth}, {"ms", t.milliseconds}});
    StageTotals totals = stage_totals(s);
    nlohmann::json per_stage;
    for (size_t i = 0; i < stage_count; ++i) per_stage[stage_name(Stage(i))] = totals.by_stage[i];
    return {{"backend", info.name},
            {"device", info.device},
            {"driver", info.driver},
            {"api_version", info.api_version},
            {"width", frame.width},
            {"height", frame.height},
            {"max_depth", settings.max_depth},
            {"exposure", settings.exposure},
            {"tone_map", settings.tone_map == ToneMap::Neutral ? "neutral" : "none"},
            {"frame_ms", s.frame_ms},
            {"host_ms", {{"enqueue", s.enqueue_ms}, {"device_wait", s.device_wait_ms}, {"readback", s.readback_ms}}},
            {"rays_per_depth", s.rays_per_depth},
            {"shadow_rays_per_depth", s.shadow_rays_per_depth},
            {"total_rays", s.total_rays()},
            {"mrays_per_second", double(s.total_rays()) / (s.frame_ms * 1e3)},
            {"stage_ms", per_stage},
            {"stages", stages},
            {"queue_capacity", s.queue_capacity},
            {"queue_regrows", s.regrows}};
}

}  // namespace prism::app
