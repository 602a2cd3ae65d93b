// What to measure: sizes, repeats and which devices. Built from the command line by bandwidth.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace prism::bandwidth {

struct DeviceFilter {
    std::string api;        // empty: any API
    std::string substring;  // matched case-insensitively against "<platform> <device>"
};

struct Plan {
    std::vector<size_t> sizes;
    int warmup = 2;
    int repeats = 10;
    std::vector<DeviceFilter> filters;  // empty: every device
    // PRISM_VULKAN_STAGING: Vulkan's pinned copies stage through "uncached" (the upload) or "cached" driver
    // memory, or through the application's own memory imported with VK_EXT_external_memory_host: "host" (huge
    // pages asked for) or "host-4k" (huge pages refused).
    std::string vulkan_staging = "uncached";
    // PRISM_VULKAN_COPY_REGIONS: each Vulkan copy command is this many regions of equal size in one vkCmdCopyBuffer
    // (whether NVIDIA's driver spreads a large copy over more copy engines when it is handed several).
    unsigned vulkan_copy_regions = 1;

    // True when the device passes the filters that name its API (or no API).
    bool wants(const std::string& api, const std::string& platform, const std::string& device) const;
};

}  // namespace prism::bandwidth
