#include "bench/bandwidth/plan.h"

#include "core/render/device_filter.h"

namespace prism::bandwidth {

bool Plan::wants(const std::string& api, const std::string& platform, const std::string& device) const {
    const std::string name = platform + " " + device;
    bool named = false;
    for (const DeviceFilter& filter : filters) {
        if (!filter.api.empty() && filter.api != api) continue;
        named = true;
        if (name_matches(name, filter.substring)) return true;
    }
    return !named;
}

}  // namespace prism::bandwidth
