#include "core/util/environment.h"

#include <array>
#include <cstdlib>

#include "core/util/error.h"

namespace prism {
namespace {

constexpr auto kSettings = std::to_array<SettingInfo>({
    {Setting::DataDir, "PRISM_DATA_DIR", "where builtin:bunny and builtin:dragon find their models"},
    {Setting::CacheDir, "PRISM_CACHE_DIR", "the OpenCL program-binary cache folder; empty turns the cache off"},
    {Setting::BvhLayout, "PRISM_BVH_LAYOUT", "the layout --bvh-layout auto picks: stack, escape or wide"},
    {Setting::CpuIsa, "PRISM_CPU_ISA", "the cpu backend's build of the stages: baseline or avx2"},
    {Setting::DeviceMemoryLimit, "PRISM_DEVICE_MEMORY_LIMIT", "bytes every GPU backend's arrays may take together"},
    {Setting::HostMemoryLimit, "PRISM_HOST_MEMORY_LIMIT", "bytes a scene and its images may take in host memory"},
    {Setting::CudaGl, "PRISM_CUDA_GL", "register: the viewer's CUDA-GL interop maps a registered GL buffer"},
    {Setting::OpenclOptions, "PRISM_OPENCL_OPTIONS", "extra OpenCL build options, after the fixed ones (experiments)"},
    {Setting::OpenclRegisters, "PRISM_OPENCL_REGISTERS",
     "stage=registers,...: NVIDIA OpenCL's per-stage register budgets in place of Prism's (experiments); none: no "
     "budgets"},
    {Setting::VulkanValidation, "PRISM_VULKAN_VALIDATION", "1: Vulkan runs under VK_LAYER_KHRONOS_validation"},
    {Setting::VulkanAddressing, "PRISM_VULKAN_ADDRESSING", "auto, descriptors or addresses: how stages reach arrays"},
    {Setting::VulkanDispatch, "PRISM_VULKAN_DISPATCH", "indirect or fixed: how Vulkan launches the queue stages"},
    {Setting::VulkanWait, "PRISM_VULKAN_WAIT", "poll or block: how Vulkan waits for a frame's fence"},
    {Setting::VulkanStaging, "PRISM_VULKAN_STAGING",
     "uncached, cached, host or host-4k: the host memory of prism bandwidth's Vulkan pinned copies"},
    {Setting::VulkanCopyRegions, "PRISM_VULKAN_COPY_REGIONS",
     "1 to 64: prism bandwidth's Vulkan copies as that many vkCmdCopyBuffer regions of equal size (default 1)"},
    {Setting::ViewPanel, "PRISM_VIEW_PANEL", "0: prism view starts without its panel"},
    {Setting::ViewAblate, "PRISM_VIEW_ABLATE", "copy or gl: prism view skips one half of showing a frame"},
    {Setting::ProgressDelay, "PRISM_PROGRESS_DELAY",
     "seconds a step runs before its progress lines start when stderr is not a terminal (default 1)"},
    {Setting::Python, "PRISM_PYTHON", "the Python with matplotlib that draws plots"},
});
// setting_name() indexes the table by the enum: one entry per Setting, in the enum's order.
static_assert(kSettings.size() == static_cast<size_t>(Setting::Python) + 1);
static_assert([] {
    for (size_t i = 0; i < kSettings.size(); ++i)
        if (kSettings[i].setting != static_cast<Setting>(i)) return false;
    return true;
}());

}  // namespace

std::span<const SettingInfo> settings() { return kSettings; }

const char* setting_name(Setting setting) { return kSettings[static_cast<size_t>(setting)].name; }

std::optional<std::string> setting(Setting which) {
    const char* value = std::getenv(setting_name(which));
    if (!value) return std::nullopt;
    return std::string(value);
}

std::string setting_choice(Setting which, std::initializer_list<const char*> choices, const std::string& who) {
    std::optional<std::string> value = setting(which);
    if (!value || value->empty()) return "";
    std::string list;
    for (const char* choice : choices) {
        if (*value == choice) return *value;
        list += list.empty() ? choice : std::string(", ") + choice;
    }
    throw Error(who + ": " + setting_name(which) + "='" + shorten(*value) + "' is not one of " + list);
}

}  // namespace prism
