// Vulkan plumbing under the backend: instance (+ validation and a debug messenger that records every warning and
// error), the choice of physical device by name, the queues a logical device is made with (the compute queue, and
// a transfer-only queue for those who ask), and memory types.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/util/non_copyable.h"

namespace prism::vk {

// Throws prism::Error("vulkan: <what> failed: <VkResult>") unless `result` is VK_SUCCESS.
void check(VkResult result, const char* what);
const char* result_name(VkResult result);

// Records a debug message (thread-safe); also what the tests read.
void record_message(const std::string& message);

bool validation_requested();  // PRISM_VULKAN_VALIDATION=1

bool has_device_extension(VkPhysicalDevice device, const char* name);

struct DeviceCandidate {
    VkPhysicalDevice handle = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceDriverProperties driver{};
    uint32_t compute_family = UINT32_MAX;   // UINT32_MAX: no compute queue
    uint32_t transfer_family = UINT32_MAX;  // transfer_only_family(); UINT32_MAX: none (e.g. lavapipe)
    std::string unusable;                   // why this device cannot run the backend ("" when it can)
    std::string describe() const;           // "llvmpipe (LLVM 15.0.6, 256 bits) [llvmpipe, Vulkan 1.3.230]"
};

class Instance : private NonCopyable {
public:
    // Throws prism::Error when there is no loader/driver or validation is requested but not installed.
    explicit Instance(bool validation);
    ~Instance();

    VkInstance handle() const { return instance_; }
    std::vector<DeviceCandidate> devices() const;
    // "" = first usable discrete/integrated GPU, else first usable device; else case-insensitive substring of the
    // device or driver name. Throws prism::Error listing the devices when nothing matches.
    DeviceCandidate select(const std::string& filter) const;
    bool validation() const { return validation_; }

private:
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    bool validation_ = false;
};

// The first family that can transfer but neither draw nor compute, or UINT32_MAX. On NVIDIA such a family feeds the
// copy engines (DMA), which work beside the SMs, so its copies may run at a different rate from the compute queue's.
uint32_t transfer_only_family(std::span<const VkQueueFamilyProperties> families);

// The queues to pass to vkCreateDevice: one on compute_family, and with `with_transfer` one on transfer_family where
// the device has that family.
std::vector<VkDeviceQueueCreateInfo> queue_create_infos(const DeviceCandidate& device, bool with_transfer);

// The queues of a device made with queue_create_infos(device, with_transfer); `transfer` is VK_NULL_HANDLE when none
// was made.
struct DeviceQueues {
    VkQueue compute = VK_NULL_HANDLE;
    VkQueue transfer = VK_NULL_HANDLE;
};
DeviceQueues get_device_queues(VkDevice device, const DeviceCandidate& candidate, bool with_transfer);

// Memory type index with all of `required`, preferring `preferred` and avoiding `avoided` flags; UINT32_MAX if none.
uint32_t find_memory_type(const VkPhysicalDeviceMemoryProperties& memory, uint32_t type_bits,
                          VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred,
                          VkMemoryPropertyFlags avoided);

// Work-groups per dispatch: kWorkGroupsPerComputeUnit (core/render/launch_config.h) x the device's compute units (SMs
// on NVIDIA through VK_NV_shader_sm_builtins, CUs on AMD through VK_AMD_shader_core_properties, host threads for a CPU
// device, else a per-type default), bounded by maxComputeWorkGroupCount[0]. The same rule as the CUDA and OpenCL
// backends.
struct GridChoice {
    uint32_t groups = 0;
    uint32_t compute_units = 0;
    std::string source;  // where compute_units came from
};
GridChoice choose_grid(const DeviceCandidate& device);

std::string api_version_string(uint32_t version);

}  // namespace prism::vk
