#include "bench/bandwidth/canvas.h"

#include <algorithm>
#include <cmath>

#include <stb_easy_font.h>
#include <stb_image_write.h>

#include "core/error.h"

namespace prism::bandwidth {

Canvas::Canvas(int width, int height, Rgb background)
    : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height * 3) {
    fill_rect(0, 0, width, height, background);
}

void Canvas::plot(int x, int y, Rgb color) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    uint8_t* p = &pixels_[(static_cast<size_t>(y) * width_ + x) * 3];
    p[0] = color.r, p[1] = color.g, p[2] = color.b;
}

void Canvas::fill_rect(int x0, int y0, int x1, int y1, Rgb color) {
    for (int y = std::max(0, y0); y < std::min(height_, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(width_, x1); ++x) plot(x, y, color);
}

void Canvas::line(double x0, double y0, double x1, double y1, Rgb color, int thickness, uint16_t dash) {
    double length = std::hypot(x1 - x0, y1 - y0);
    int steps = std::max(1, static_cast<int>(std::ceil(length)));
    for (int i = 0; i <= steps; ++i) {
        if (!(dash >> ((i / 2) % 16) & 1)) continue;
        double t = static_cast<double>(i) / steps;
        int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))) - thickness / 2;
        int y = static_cast<int>(std::lround(y0 + t * (y1 - y0))) - thickness / 2;
        fill_rect(x, y, x + thickness, y + thickness, color);
    }
}

void Canvas::text(int x, int y, const std::string& text, Rgb color, int scale, bool vertical) {
    // stb_easy_font emits quads of 4 vertices {x, y, z, rgba}: 16 bytes per vertex.
    std::vector<char> vertices(text.size() * 700 + 64);
    std::string copy = text;
    int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, vertices.data(), static_cast<int>(vertices.size()));
    for (int q = 0; q < quads; ++q) {
        const float* v = reinterpret_cast<const float*>(vertices.data() + q * 64);
        float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9];   // vertices 0 and 2 are opposite corners
        int ax0 = static_cast<int>(std::lround(std::min(qx0, qx1) * scale));
        int ax1 = static_cast<int>(std::lround(std::max(qx0, qx1) * scale));
        int ay0 = static_cast<int>(std::lround(std::min(qy0, qy1) * scale));
        int ay1 = static_cast<int>(std::lround(std::max(qy0, qy1) * scale));
        if (vertical)   // rotate 90 degrees counter-clockwise about (x, y): text runs upwards
            fill_rect(x + ay0, y - ax1, x + ay1, y - ax0, color);
        else
            fill_rect(x + ax0, y + ay0, x + ax1, y + ay1, color);
    }
}

int Canvas::text_width(const std::string& text, int scale) {
    std::string copy = text;
    return stb_easy_font_width(copy.data()) * scale;
}

void Canvas::write_png(const std::filesystem::path& path) const {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    if (!stbi_write_png(path.string().c_str(), width_, height_, 3, pixels_.data(), width_ * 3))
        throw Error(path.string() + ": cannot write PNG");
}

}  // namespace prism::bandwidth
