// A tiny RGB raster for the bandwidth plot: lines (with dash patterns), rectangles and text. Text comes from
// stb_easy_font, a public-domain built-in stroke font, so no font file is needed at run time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace prism::bandwidth {

struct Rgb {
    uint8_t r, g, b;
};

class Canvas {
public:
    Canvas(int width, int height, Rgb background);
    int width() const { return width_; }
    int height() const { return height_; }

    void fill_rect(int x0, int y0, int x1, int y1, Rgb color);   // inclusive-exclusive
    // `dash` is a bit pattern over 16 steps of 2 pixels (0xFFFF: solid).
    void line(double x0, double y0, double x1, double y1, Rgb color, int thickness = 2, uint16_t dash = 0xFFFF);
    // Top-left at (x, y); `scale` multiplies the font's ~6x9 pixel glyphs. `vertical` writes bottom to top.
    void text(int x, int y, const std::string& text, Rgb color, int scale = 1, bool vertical = false);
    static int text_width(const std::string& text, int scale = 1);

    // Throws prism::Error("<path>: cannot write PNG") on failure.
    void write_png(const std::filesystem::path& path) const;

private:
    void plot(int x, int y, Rgb color);
    int width_, height_;
    std::vector<uint8_t> pixels_;
};

}  // namespace prism::bandwidth
