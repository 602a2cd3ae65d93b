#include "core/image/image_compare.h"

#include <cmath>
#include <limits>

namespace prism {

double psnr_rgba8(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size() || a.empty()) return 0.0;
    double squared = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double d = double((a[i] >> (8 * c)) & 255u) - double((b[i] >> (8 * c)) & 255u);
            squared += d * d;
        }
    double mse = squared / (3.0 * double(a.size()));
    return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace prism
