#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "bench/bandwidth/canvas.h"
#include "bench/bandwidth/report.h"
#include "bench/bandwidth/sizes.h"

namespace prism::bandwidth {
namespace {

struct Series {
    std::string label;
    Rgb color;
    uint16_t dash;
    std::vector<std::pair<double, double>> points;   // (bytes, GB/s)
};

// Colour tells the kind of copy, the dash pattern the API/device, so one legend reads both ways.
std::vector<Series> collect_series(const Report& report) {
    const std::pair<Direction, Memory> kinds[] = {
        {Direction::HostToDevice, Memory::Pageable}, {Direction::HostToDevice, Memory::Pinned},
        {Direction::DeviceToHost, Memory::Pageable}, {Direction::DeviceToHost, Memory::Pinned},
        {Direction::DeviceToDevice, Memory::Device}, {Direction::KernelCopy, Memory::Device}};
    const Rgb colors[] = {{120, 170, 230}, {20, 80, 200}, {240, 170, 90}, {210, 90, 0}, {30, 150, 60}, {170, 40, 160}};
    const uint16_t dashes[] = {0xFFFF, 0x0FFF, 0x3333, 0x0F0F, 0x5555, 0x00FF};
    std::vector<Series> series;
    int device_index = 0;
    for (const ApiResult& api : report.apis)
        for (const DeviceResult& device : api.devices) {
            for (size_t k = 0; k < std::size(kinds); ++k) {
                Series s{device.api + " " + device.device.substr(0, 28) + ": " + direction_label(kinds[k].first) +
                             " " + memory_key(kinds[k].second),
                         colors[k], dashes[device_index % std::size(dashes)], {}};
                for (const Measurement& m : device.measurements)
                    if (m.direction == kinds[k].first && m.memory == kinds[k].second)
                        s.points.emplace_back(static_cast<double>(m.bytes), m.primary_gbps());
                std::sort(s.points.begin(), s.points.end());
                if (!s.points.empty()) series.push_back(std::move(s));
            }
            ++device_index;
        }
    return series;
}

std::string number_label(double value) {
    char text[32];
    if (value >= 1) std::snprintf(text, sizeof text, "%.0f", value);
    else std::snprintf(text, sizeof text, "%g", value);
    return text;
}

}  // namespace

void write_plot(const Report& report, const std::filesystem::path& path) {
    const Rgb white{255, 255, 255}, black{0, 0, 0}, grid{225, 225, 225}, minor{242, 242, 242};
    Canvas canvas(plot_width, plot_height, white);
    const int left = 90, right = plot_width - 400, top = 60, bottom = plot_height - 80;
    std::vector<Series> series = collect_series(report);

    // Axis ranges: whole powers of 4 in x (the sweep's steps), whole decades in y.
    double size_min = 1e300, size_max = 0, rate_min = 1e300, rate_max = 0;
    for (size_t bytes : report.plan.sizes) size_min = std::min(size_min, double(bytes)), size_max = std::max(size_max, double(bytes));
    for (const Series& s : series)
        for (auto [bytes, gbps] : s.points) rate_min = std::min(rate_min, gbps), rate_max = std::max(rate_max, gbps);
    if (series.empty()) rate_min = 0.1, rate_max = 10;
    double x_low = std::floor(std::log2(size_min) / 2) * 2, x_high = std::ceil(std::log2(size_max) / 2) * 2;
    if (x_high - x_low < 4) x_low -= 2, x_high += 2;
    double y_low = std::floor(std::log10(rate_min)), y_high = std::ceil(std::log10(rate_max));
    if (y_high - y_low < 1) y_high = y_low + 1;
    auto to_x = [&](double bytes) { return left + (std::log2(bytes) - x_low) / (x_high - x_low) * (right - left); };
    auto to_y = [&](double gbps) { return bottom - (std::log10(gbps) - y_low) / (y_high - y_low) * (bottom - top); };

    for (double decade = y_low; decade <= y_high; ++decade) {
        for (int m = 2; m < 10 && decade < y_high; ++m)
            canvas.line(left, to_y(m * std::pow(10, decade)), right, to_y(m * std::pow(10, decade)), minor, 1);
        double y = to_y(std::pow(10, decade));
        canvas.line(left, y, right, y, grid, 1);
        std::string label = number_label(std::pow(10, decade));
        canvas.text(left - 8 - Canvas::text_width(label, 2), static_cast<int>(y) - 7, label, black, 2);
    }
    for (double step = x_low; step <= x_high; step += 2) {
        double x = to_x(std::pow(2, step));
        canvas.line(x, top, x, bottom, grid, 1);
        std::string label = format_size(static_cast<size_t>(std::pow(2, step)));
        canvas.text(static_cast<int>(x) - Canvas::text_width(label, 2) / 2, bottom + 10, label, black, 2);
    }
    canvas.line(left, bottom, right, bottom, black, 2);
    canvas.line(left, top, left, bottom, black, 2);

    canvas.text(left, 18, "prism bandwidth: median GB/s against transfer size (log-log)", black, 2);
    std::string x_title = "transfer size (bytes, log scale)";
    canvas.text((left + right) / 2 - Canvas::text_width(x_title, 2) / 2, bottom + 40, x_title, black, 2);
    canvas.text(14, (top + bottom) / 2 + Canvas::text_width("GB/s (1e9 bytes/s)", 2) / 2, "GB/s (1e9 bytes/s)", black, 2,
                true);

    for (const Series& s : series) {
        for (size_t i = 1; i < s.points.size(); ++i)
            canvas.line(to_x(s.points[i - 1].first), to_y(s.points[i - 1].second), to_x(s.points[i].first),
                        to_y(s.points[i].second), s.color, 2, s.dash);
        for (auto [bytes, gbps] : s.points) {
            int x = static_cast<int>(to_x(bytes)), y = static_cast<int>(to_y(gbps));
            canvas.fill_rect(x - 3, y - 3, x + 4, y + 4, s.color);
        }
    }

    // Legend: sample line + marker + label, one row per series.
    int legend_x = right + 20, legend_y = top;
    canvas.text(legend_x, legend_y - 22, "D2D rows: bytes copied/s (r+w = 2x)", black, 1);
    for (const Series& s : series) {
        if (legend_y > plot_height - 20) break;
        canvas.line(legend_x, legend_y + 5, legend_x + 36, legend_y + 5, s.color, 2, s.dash);
        canvas.fill_rect(legend_x + 15, legend_y + 2, legend_x + 22, legend_y + 9, s.color);
        canvas.text(legend_x + 44, legend_y, s.label, black, 1);
        legend_y += 16;
    }
    if (series.empty()) canvas.text(left + 20, top + 20, "no measurements", black, 2);
    canvas.write_png(path);
}

}  // namespace prism::bandwidth
