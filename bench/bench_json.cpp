#include "bench/bench_json.h"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

#include "core/util/build_info.h"
#include "core/util/error.h"
#include "core/util/standard_output.h"

namespace prism::bench {

static std::string cpu_model() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos) return line.substr(colon + 2);
        }
    }
    return "unknown";
}

nlohmann::json result_header() {
    std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return {{"commit", build_commit()},
            {"date", date},
            {"build_type", build_type()},
            {"host", {{"cpu", cpu_model()}, {"threads", std::thread::hardware_concurrency()}}}};
}

void write_result(const std::filesystem::path& path, const nlohmann::json& result) {
    if (path == "-") {
        write_standard_output(result.dump(2) + "\n");
        return;
    }
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path);
    if (!out) throw Error(path.string() + ": cannot open for writing");
    out << result.dump(2) << "\n";
    if (!out) throw Error(path.string() + ": write failed");
    std::printf("wrote %s\n", path.string().c_str());
}

nlohmann::json kernel_resources_json(const KernelResources& resources) {
    auto known = [](long long value) { return value < 0 ? nlohmann::json(nullptr) : nlohmann::json(value); };
    nlohmann::json stages = nlohmann::json::array();
    for (const StageResources& stage : resources.stages) {
        nlohmann::json statistics = nlohmann::json::object();
        for (const auto& [name, value] : stage.statistics) statistics[name] = value;
        stages.push_back({{"stage", stage_name(stage.stage)},
                          {"registers", known(stage.registers)},
                          {"private_bytes", known(stage.private_bytes)},
                          {"shared_bytes", known(stage.shared_bytes)},
                          {"statistics", statistics}});
    }
    return {{"source", resources.source}, {"stages", stages}};
}

}  // namespace prism::bench
