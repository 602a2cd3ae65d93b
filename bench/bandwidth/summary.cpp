#include "bench/bandwidth/summary.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

namespace prism::bandwidth {

// The queues this kind of copy was measured on, in the order measured: {""} for APIs without a choice of queue.
static std::vector<std::string> queues_of(const DeviceResult& device, Direction direction, Memory memory) {
    std::vector<std::string> queues;
    for (const Measurement& m : device.measurements)
        if (m.direction == direction && m.memory == memory &&
            std::find(queues.begin(), queues.end(), m.queue) == queues.end())
            queues.push_back(m.queue);
    return queues;
}

double read_write_gbps(const Measurement& measurement, double gbps) {
    return counts_read_and_write(measurement.direction) ? 2 * gbps : gbps;
}

std::vector<SummaryRow> summarize_peaks(const std::vector<ApiResult>& apis) {
    const std::pair<Direction, Memory> kinds[] = {
        {Direction::HostToDevice, Memory::Pageable}, {Direction::HostToDevice, Memory::Pinned},
        {Direction::DeviceToHost, Memory::Pageable}, {Direction::DeviceToHost, Memory::Pinned},
        {Direction::DeviceToDevice, Memory::Device}, {Direction::KernelCopy, Memory::Device}};

    std::map<std::string, std::optional<double>> memory_spec;
    std::map<std::string, std::optional<LinkInfo>> link;
    for (const ApiResult& api : apis)
        for (const DeviceResult& device : api.devices) {
            if (device.memory_spec_gbps && !memory_spec[device.device])
                memory_spec[device.device] = device.memory_spec_gbps;
            if (device.link && (!link[device.device] || link[device.device]->gbps < device.link->gbps))
                link[device.device] = device.link;
        }

    std::vector<SummaryRow> rows;
    for (const ApiResult& api : apis)
        for (const DeviceResult& device : api.devices)
            for (auto [direction, memory] : kinds)
                for (const std::string& queue : queues_of(device, direction, memory)) {
                    const Measurement* peak = nullptr;
                    for (const Measurement& m : device.measurements)
                        if (m.direction == direction && m.memory == memory && m.queue == queue &&
                            (!peak || m.primary_gbps() > peak->primary_gbps()))
                            peak = &m;
                    SummaryRow row{&device, peak};
                    bool to_memory = counts_read_and_write(direction);
                    char spec[96];
                    if (to_memory && memory_spec[device.device]) {
                        double gbps = *memory_spec[device.device];
                        row.percent_of_spec = 100 * read_write_gbps(*peak, peak->primary_gbps()) / gbps;
                        std::snprintf(spec, sizeof spec, "memory %.0f GB/s (r+w)", gbps);
                        row.spec = spec;
                    } else if (!to_memory && link[device.device]) {
                        const LinkInfo& info = *link[device.device];
                        row.percent_of_spec = 100 * peak->primary_gbps() / info.gbps;
                        std::snprintf(spec, sizeof spec, "%s (%.1f GB/s)", info.description.c_str(), info.gbps);
                        row.spec = spec;
                    }
                    rows.push_back(row);
                }

    // Best API (and queue) per (device name, kind of copy).
    std::map<std::tuple<std::string, Direction, Memory>, double> best;
    for (const SummaryRow& row : rows) {
        double& b = best[{row.device->device, row.peak->direction, row.peak->memory}];
        b = std::max(b, row.peak->primary_gbps());
    }
    for (SummaryRow& row : rows)
        row.percent_of_best =
            100 * row.peak->primary_gbps() / best[{row.device->device, row.peak->direction, row.peak->memory}];
    return rows;
}

}  // namespace prism::bandwidth
