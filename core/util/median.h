// The median the benchmarks and the viewer's frame timing report (the mean of the middle two of an even count;
// 0 for none): robust to the odd slow run a busy machine or a driver's first launch adds.
#pragma once

#include <algorithm>
#include <vector>

namespace prism {

inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace prism
