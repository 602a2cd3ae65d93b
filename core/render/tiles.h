// Splitting one frame into tiles that devices or MPI ranks render apart (RenderSettings::region), and putting the
// tiles back together. Fixed-point accumulation makes a tile's pixels bit-identical to the whole frame's, so the
// assembled image equals the one-device render exactly.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/render/renderer.h"

namespace prism {

// Tiles of at most tile_size x tile_size pixels, row by row from the top-left; they cover the image exactly once.
// Throws prism::Error for a tile size of 0.
std::vector<PixelRect> split_into_tiles(uint32_t width, uint32_t height, uint32_t tile_size);

// Copies a region's pixels (row-major, `channels` values each) into the whole image of `image_width` pixels a row.
template <typename T>
void place_region(std::span<T> image, uint32_t image_width, const PixelRect& region, std::span<const T> pixels,
                  uint32_t channels = 1) {
    const size_t row = size_t(region.width) * channels;
    for (uint32_t y = 0; y < region.height; ++y) {
        const T* from = pixels.data() + y * row;
        T* to = image.data() + (size_t(region.y + y) * image_width + region.x) * channels;
        for (size_t i = 0; i < row; ++i) to[i] = from[i];
    }
}

}  // namespace prism
