// The outputs of `prism bandwidth`: text tables on stdout and the JSON result file (bench/plot_bench.py draws the
// plot from that JSON).
#pragma once

#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bandwidth/measurement.h"
#include "bench/bandwidth/plan.h"

namespace prism::bandwidth {

struct Report {
    Plan plan;
    std::vector<ApiResult> apis;
};

// Devices, the peak table (Figure 8-1 layout), the per-size sweep, notes and skipped APIs.
void print_report(const Report& report, std::FILE* out);

// The result file; its schema is documented in docs/bandwidth.md ("prism-bandwidth/1").
inline constexpr const char* json_schema_name = "prism-bandwidth/1";
nlohmann::json report_json(const Report& report);

}  // namespace prism::bandwidth
