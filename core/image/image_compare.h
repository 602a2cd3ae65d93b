// Image agreement as the tests and benchmarks measure it: PSNR over the RGB channels of 8-bit images.
#pragma once

#include <cstdint>
#include <vector>

namespace prism {

// Peak signal-to-noise ratio in dB of two RGBA8 images (r in the low byte), RGB only; +infinity when identical,
// 0 when the sizes differ or the images are empty.
double psnr_rgba8(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b);

}  // namespace prism
