#include <string>

#include "bench/bandwidth/report.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bandwidth/summary.h"

namespace prism::bandwidth {

static std::string clip(const std::string& text, size_t width) {
    return text.size() <= width ? text : text.substr(0, width - 1) + "~";
}

static std::string copy_label(const Measurement& m) {
    std::string label = std::string(direction_label(m.direction)) + " " + memory_key(m.memory);
    return m.queue.empty() ? label : label + " [" + m.queue + "]";
}

void print_report(const Report& report, std::FILE* out) {
    const Plan& plan = report.plan;
    std::fprintf(out, "prism bandwidth: %zu size%s, %d warm-up, median of %d\n", plan.sizes.size(),
                 plan.sizes.size() == 1 ? "" : "s", plan.warmup, plan.repeats);
    std::fprintf(out,
                 "GB/s = 1e9 bytes/s. device = cudaEvent / OpenCL profiling events / vkCmdWriteTimestamp;\n"
                 "wall = host clock around issue and wait. D2D copy and D2D kernel are bytes copied per second;\n"
                 "r+w = read+write traffic (2x bytes copied, as CUDA's bandwidthTest counts).\n"
                 "[compute] / [transfer] = the Vulkan queue the copy command ran on.\n\n");

    std::fprintf(out, "Devices\n");
    for (const ApiResult& api : report.apis)
        for (const DeviceResult& d : api.devices) {
            std::fprintf(out, "  %-7s %s | %s | driver %s%s%s\n", d.api.c_str(), d.device.c_str(),
                         d.api_version.c_str(), d.driver.c_str(), d.pci_address.empty() ? "" : " | PCI ",
                         d.pci_address.c_str());
            for (const std::string& detail : d.details) std::fprintf(out, "          %s\n", detail.c_str());
        }

    std::fprintf(out, "\nPeak bandwidth (best median over sizes; %% best = of the best API on the same device)\n");
    std::fprintf(out, "%-7s %-28s %-26s %6s %9s %9s %9s %7s %7s  %s\n", "API", "Device", "Copy", "Size", "Device",
                 "Wall", "r+w", "% best", "% spec", "Spec");
    for (const SummaryRow& row : summarize_peaks(report.apis)) {
        const Measurement& m = *row.peak;
        char rate[16] = "-", read_write[16] = "", spec[16] = "";
        if (m.device_timer) std::snprintf(rate, sizeof rate, "%.2f", m.device_timer->median_gbps);
        if (counts_read_and_write(m.direction))
            std::snprintf(read_write, sizeof read_write, "%.2f", read_write_gbps(m, m.primary_gbps()));
        if (row.percent_of_spec) std::snprintf(spec, sizeof spec, "%.1f", *row.percent_of_spec);
        std::fprintf(out, "%-7s %-28s %-26s %6s %9s %9.2f %9s %7.1f %7s  %s\n", row.device->api.c_str(),
                     clip(row.device->device, 28).c_str(), copy_label(m).c_str(), format_size(m.bytes).c_str(), rate,
                     m.wall.median_gbps, read_write, row.percent_of_best, spec, row.spec.c_str());
    }

    std::fprintf(out, "\nSweep: median GB/s by size (device timer; * = wall time, no device timer)\n");
    std::fprintf(out, "%-7s %-20s %-26s", "API", "Device", "Copy");
    for (size_t bytes : plan.sizes) std::fprintf(out, " %8s", format_size(bytes).c_str());
    std::fprintf(out, "\n");
    for (const SummaryRow& row : summarize_peaks(report.apis)) {
        std::fprintf(out, "%-7s %-20s %-26s", row.device->api.c_str(), clip(row.device->device, 20).c_str(),
                     copy_label(*row.peak).c_str());
        for (size_t bytes : plan.sizes) {
            const Measurement* found = nullptr;
            for (const Measurement& m : row.device->measurements)
                if (m.bytes == bytes && m.direction == row.peak->direction && m.memory == row.peak->memory &&
                    m.queue == row.peak->queue)
                    found = &m;
            char cell[16] = "-";
            if (found)
                std::snprintf(cell, sizeof cell, "%.2f%s", found->primary_gbps(), found->device_timer ? "" : "*");
            std::fprintf(out, " %8s", cell);
        }
        std::fprintf(out, "\n");
    }

    bool any_note = false;
    for (const ApiResult& api : report.apis)
        for (const DeviceResult& d : api.devices)
            for (const std::string& note : d.notes) {
                if (!any_note) std::fprintf(out, "\nNotes\n");
                any_note = true;
                std::fprintf(out, "  %s %s: %s\n", d.api.c_str(), d.device.c_str(), note.c_str());
            }
    bool any_skipped = false;
    for (const ApiResult& api : report.apis)
        if (!api.unavailable_reason.empty()) {
            if (!any_skipped) std::fprintf(out, "\nSkipped\n");
            any_skipped = true;
            std::fprintf(out, "  %s: %s\n", api.api.c_str(), api.unavailable_reason.c_str());
        }
    std::fflush(out);
}

}  // namespace prism::bandwidth
