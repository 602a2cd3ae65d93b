#include "bench/bandwidth/plan.h"

#include <algorithm>
#include <cctype>

namespace prism::bandwidth {

static std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
}

bool Plan::wants(const std::string& api, const std::string& platform, const std::string& device) const {
    std::string name = lower(platform + " " + device);
    bool named = false;
    for (const DeviceFilter& filter : filters) {
        if (!filter.api.empty() && filter.api != api) continue;
        named = true;
        if (name.find(lower(filter.substring)) != std::string::npos) return true;
    }
    return !named;
}

}  // namespace prism::bandwidth
