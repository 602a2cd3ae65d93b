// What every bench/ result file records besides its numbers (architecture.md, "Benchmark method").
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/render/backend.h"

namespace prism::bench {

// {"commit", "date" (UTC, ISO 8601), "build_type", "host" (CPU model, cores)}; callers add device/driver/API.
nlohmann::json result_header();
// Writes pretty JSON to `path`, creating parent folders, and prints the path; "-" writes it to standard output
// (core/util/standard_output.h).
void write_result(const std::filesystem::path& path, const nlohmann::json& result);

// {"source", "stages": [{"stage", "registers", "private_bytes", "shared_bytes", "statistics"}]}: what each stage's
// kernel got from its API's compiler, a value the API does not report as null.
nlohmann::json kernel_resources_json(const KernelResources& resources);

}  // namespace prism::bench
