// Every PRISM_* environment variable Prism reads, in one table, and the one place that reads them: code asks for a
// Setting, never calls getenv itself for one. docs/environment.md lists them for users.
#pragma once

#include <initializer_list>
#include <optional>
#include <span>
#include <string>

namespace prism {

enum class Setting {
    DataDir,            // PRISM_DATA_DIR
    CacheDir,           // PRISM_CACHE_DIR
    BvhLayout,          // PRISM_BVH_LAYOUT
    CpuIsa,             // PRISM_CPU_ISA
    DeviceMemoryLimit,  // PRISM_DEVICE_MEMORY_LIMIT
    HostMemoryLimit,    // PRISM_HOST_MEMORY_LIMIT
    CudaGl,             // PRISM_CUDA_GL
    OpenclOptions,      // PRISM_OPENCL_OPTIONS
    OpenclRegisters,    // PRISM_OPENCL_REGISTERS
    VulkanValidation,   // PRISM_VULKAN_VALIDATION
    VulkanAddressing,   // PRISM_VULKAN_ADDRESSING
    VulkanDispatch,     // PRISM_VULKAN_DISPATCH
    VulkanWait,         // PRISM_VULKAN_WAIT
    VulkanStaging,      // PRISM_VULKAN_STAGING
    VulkanCopyRegions,  // PRISM_VULKAN_COPY_REGIONS
    ViewPanel,          // PRISM_VIEW_PANEL
    ViewAblate,         // PRISM_VIEW_ABLATE
    ProgressDelay,      // PRISM_PROGRESS_DELAY
    Python,             // PRISM_PYTHON
};

struct SettingInfo {
    Setting setting;
    const char* name;    // "PRISM_CPU_ISA"
    const char* effect;  // one line for users
};

// The whole table, in the order above.
std::span<const SettingInfo> settings();
const char* setting_name(Setting setting);

// The variable's value; nullopt when unset. An empty value is returned as "" (PRISM_CACHE_DIR="" turns the cache
// off); most callers treat it as unset.
std::optional<std::string> setting(Setting setting);

// The value when set and not empty, which must be one of `choices`; "" when unset or empty. Throws prism::Error
// "<who>: <NAME>='<value>' is not one of a, b" otherwise.
std::string setting_choice(Setting setting, std::initializer_list<const char*> choices, const std::string& who);

}  // namespace prism
