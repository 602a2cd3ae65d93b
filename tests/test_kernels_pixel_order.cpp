// The primary rays' order (rt_primary_pixel, kernels/stages.h): every pixel of the tile exactly once, in squares
// of RT_PIXEL_BLOCK pixels, whatever the tile's size.
#include <gtest/gtest.h>

#include <vector>

#include "kernels/stages.h"

namespace {

TEST(PrimaryPixelOrder, VisitsEveryPixelOnceForAnySize) {
    for (uint width : {1u, 7u, 31u, 32u, 33u, 64u, 100u, 161u, 400u, 1920u})
        for (uint height : {1u, 5u, 32u, 45u, 99u, 250u}) {
            std::vector<int> seen(size_t(width) * height, 0);
            for (uint i = 0; i < width * height; ++i) {
                uint pixel = rt_primary_pixel(i, width, height);
                ASSERT_LT(pixel, width * height) << width << "x" << height << " index " << i;
                seen[pixel] += 1;
            }
            for (size_t p = 0; p < seen.size(); ++p) ASSERT_EQ(seen[p], 1) << width << "x" << height << " pixel " << p;
        }
}

TEST(PrimaryPixelOrder, WalksSquaresRowByRow) {
    const uint width = 100, height = 70;  // three full squares and a 4-wide rest per band; a 6-high last band
    EXPECT_EQ(rt_primary_pixel(0, width, height), 0u);
    EXPECT_EQ(rt_primary_pixel(31, width, height), 31u);
    EXPECT_EQ(rt_primary_pixel(32, width, height), width);            // the square's second row
    EXPECT_EQ(rt_primary_pixel(32 * 32, width, height), 32u);         // the next square
    EXPECT_EQ(rt_primary_pixel(3 * 32 * 32, width, height), 96u);     // the band's 4-wide rest
    EXPECT_EQ(rt_primary_pixel(3 * 32 * 32 + 4, width, height), width + 96u);
    EXPECT_EQ(rt_primary_pixel(32 * width, width, height), 32 * width);  // the second band
    uint last_band = 64 * width;
    EXPECT_EQ(rt_primary_pixel(last_band + 32, width, height), last_band + width);  // a 6-high square: 32 wide
    EXPECT_EQ(rt_primary_pixel(last_band + 6 * 32, width, height), last_band + 32u);
}

}  // namespace
