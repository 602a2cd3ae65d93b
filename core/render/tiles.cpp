#include "core/render/tiles.h"

#include <algorithm>
#include <string>

#include "core/util/error.h"

namespace prism {

std::vector<PixelRect> split_into_tiles(uint32_t width, uint32_t height, uint32_t tile_size) {
    if (tile_size == 0) throw Error("tile size 0 is out of range (1 or more pixels)");
    std::vector<PixelRect> tiles;
    for (uint32_t y = 0; y < height; y += tile_size)
        for (uint32_t x = 0; x < width; x += tile_size)
            tiles.push_back(PixelRect{x, y, std::min(tile_size, width - x), std::min(tile_size, height - y)});
    return tiles;
}

}  // namespace prism
