// How a rendered frame is reported: the human summary printed by `prism render`/`view` and the --stats JSON.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/render/backend.h"
#include "core/render/renderer.h"

namespace prism::app {

struct StageTotals {
    double by_stage[stage_count] = {};
    double total() const;
};
StageTotals stage_totals(const FrameStats& stats);

std::string frame_summary(const FrameResult& frame, const RenderSettings& settings);
nlohmann::json frame_json(const FrameResult& frame, const RenderSettings& settings, const BackendInfo& info);

}  // namespace prism::app
