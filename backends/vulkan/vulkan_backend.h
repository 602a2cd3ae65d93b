// The `vulkan` backend: kernels/ compiled to SPIR-V (shaders/, embedded at build time) and run as compute
// pipelines. "vulkan" picks the first discrete or integrated GPU, else the first device; "vulkan:<text>" the first
// device whose name or driver name contains <text> (case-insensitive), e.g. vulkan:llvmpipe, vulkan:nvidia.
//
// PRISM_VULKAN_VALIDATION=1 enables VK_LAYER_KHRONOS_validation; every warning or error any layer or driver
// reports through VK_EXT_debug_utils is recorded (and printed to stderr) and can be read back by the tests.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/render/backend.h"

namespace prism {

BackendFactory vulkan_backend_factory();

// Debug messages (warnings and errors) recorded since the last clear, from every Vulkan backend of the process.
std::vector<std::string> vulkan_debug_messages();
void vulkan_clear_debug_messages();

// For the layout test: an embedded SPIR-V module by shader name ("layout_check", "generate", ...); empty if none.
std::span<const uint32_t> vulkan_embedded_spirv(std::string_view name);
// Runs `spirv` (entry "main", the stage shaders' descriptor set and push constant) as `groups` work-groups on a
// Vulkan backend, ordered with its other commands. Throws prism::Error if `backend` is not a Vulkan backend.
void vulkan_dispatch_module(Backend& backend, std::span<const uint32_t> spirv, uint32_t groups, uint32_t push = 0);

// How a Vulkan backend runs its stages at this moment: through buffer device addresses (an array is larger than
// maxStorageBufferRange, or PRISM_VULKAN_ADDRESSING=addresses) or descriptors, and sized by indirect dispatch or
// as the fixed grid (PRISM_VULKAN_DISPATCH=fixed). Throws prism::Error if `backend` is not a Vulkan backend.
struct VulkanLaunchMode {
    bool addresses = false;
    bool indirect = false;
    bool polls_fence = false;  // the host polls a frame's fence instead of sleeping in vkWaitForFences
};
VulkanLaunchMode vulkan_launch_mode(const Backend& backend);

}  // namespace prism
