#include "bench/bandwidth/report.h"
#include "bench/bandwidth/summary.h"
#include "bench/bench_json.h"

namespace prism::bandwidth {

static nlohmann::json rate_json(const RateStats& stats, const Measurement& m) {
    nlohmann::json json = {{"median_gbps", stats.median_gbps},
                           {"min_gbps", stats.min_gbps},
                           {"max_gbps", stats.max_gbps},
                           {"median_seconds", stats.median_seconds}};
    if (counts_read_and_write(m.direction)) json["read_write_median_gbps"] = read_write_gbps(m, stats.median_gbps);
    return json;
}

static nlohmann::json optional_number(const std::optional<double>& value) {
    return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// Only where the API chose a queue, so CUDA and OpenCL entries, and files written before Vulkan's queues were told
// apart, keep one form.
static void add_queue(nlohmann::json& entry, const Measurement& m) {
    if (!m.queue.empty()) entry["queue"] = m.queue;
}

nlohmann::json report_json(const Report& report) {
    nlohmann::json json = bench::result_header();  // commit, date, build_type, host
    json["schema"] = json_schema_name;
    json["sizes"] = report.plan.sizes;
    json["warmup"] = report.plan.warmup;
    json["repeats"] = report.plan.repeats;
    json["gbps_definition"] = "1e9 bytes copied per second; read_write_* doubles device-to-device copies";

    json["devices"] = nlohmann::json::array();
    json["skipped_apis"] = nlohmann::json::array();
    for (const ApiResult& api : report.apis) {
        if (!api.unavailable_reason.empty())
            json["skipped_apis"].push_back({{"api", api.api}, {"reason", api.unavailable_reason}});
        for (const DeviceResult& d : api.devices) {
            nlohmann::json device = {{"api", d.api},
                                     {"device", d.device},
                                     {"platform", d.platform},
                                     {"driver", d.driver},
                                     {"api_version", d.api_version},
                                     {"pci_address", d.pci_address},
                                     {"device_memory_bytes", d.device_memory},
                                     {"memory_spec_gbps", optional_number(d.memory_spec_gbps)},
                                     {"link", nullptr},
                                     {"details", d.details},
                                     {"notes", d.notes},
                                     {"measurements", nlohmann::json::array()}};
            if (d.link) device["link"] = {{"description", d.link->description}, {"gbps", d.link->gbps}};
            for (const Measurement& m : d.measurements) {
                nlohmann::json measurement = {
                    {"direction", direction_key(m.direction)},
                    {"memory", memory_key(m.memory)},
                    {"bytes", m.bytes},
                    {"device_timer", m.device_timer ? rate_json(*m.device_timer, m) : nlohmann::json(nullptr)},
                    {"wall", rate_json(m.wall, m)}};
                add_queue(measurement, m);
                device["measurements"].push_back(measurement);
            }
            json["devices"].push_back(device);
        }
    }

    json["summary"] = nlohmann::json::array();
    for (const SummaryRow& row : summarize_peaks(report.apis)) {
        nlohmann::json summary = {{"api", row.device->api},
                                  {"device", row.device->device},
                                  {"direction", direction_key(row.peak->direction)},
                                  {"memory", memory_key(row.peak->memory)},
                                  {"bytes", row.peak->bytes},
                                  {"gbps", row.peak->primary_gbps()},
                                  {"timer", row.peak->device_timer ? "device" : "wall"},
                                  {"percent_of_best_api", row.percent_of_best},
                                  {"percent_of_spec", optional_number(row.percent_of_spec)},
                                  {"spec", row.spec}};
        add_queue(summary, *row.peak);
        json["summary"].push_back(summary);
    }
    return json;
}

}  // namespace prism::bandwidth
