#include "backends/vulkan/vulkan_context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include "backends/vulkan/vulkan_backend.h"
#include "core/render/backend.h"
#include "core/render/device_filter.h"
#include "core/util/environment.h"
#include "core/util/error.h"
#include "core/render/launch_config.h"

namespace prism {
namespace {

std::mutex& message_mutex() {
    static std::mutex mutex;
    return mutex;
}
std::vector<std::string>& message_log() {
    static std::vector<std::string> log;
    return log;
}

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    const char* level = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    std::string text = std::string("vulkan ") + level + ": " + (data && data->pMessage ? data->pMessage : "(no text)");
    vk::record_message(text);
    std::fprintf(stderr, "%s\n", text.c_str());
    return VK_FALSE;
}

}  // namespace

std::vector<std::string> vulkan_debug_messages() {
    std::lock_guard lock(message_mutex());
    return message_log();
}

void vulkan_clear_debug_messages() {
    std::lock_guard lock(message_mutex());
    message_log().clear();
}

namespace vk {

bool has_device_extension(VkPhysicalDevice device, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
    for (const VkExtensionProperties& e : extensions)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

void record_message(const std::string& message) {
    std::lock_guard lock(message_mutex());
    message_log().push_back(message);
}

bool validation_requested() { return setting(Setting::VulkanValidation) == "1"; }

const char* result_name(VkResult result) {
    switch (result) {
#define PRISM_VK_RESULT(name) \
    case name: return #name;
        PRISM_VK_RESULT(VK_SUCCESS)
        PRISM_VK_RESULT(VK_NOT_READY)
        PRISM_VK_RESULT(VK_TIMEOUT)
        PRISM_VK_RESULT(VK_INCOMPLETE)
        PRISM_VK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        PRISM_VK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        PRISM_VK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        PRISM_VK_RESULT(VK_ERROR_DEVICE_LOST)
        PRISM_VK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        PRISM_VK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        PRISM_VK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        PRISM_VK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        PRISM_VK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        PRISM_VK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        PRISM_VK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        PRISM_VK_RESULT(VK_ERROR_FRAGMENTED_POOL)
        PRISM_VK_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
        PRISM_VK_RESULT(VK_ERROR_INVALID_SHADER_NV)
#undef PRISM_VK_RESULT
        default: return "VkResult error";
    }
}

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS)
        throw Error(std::string("vulkan: ") + what + " failed: " + result_name(result) + " (" +
                    std::to_string(int(result)) + ")");
}

std::string api_version_string(uint32_t version) {
    return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) + "." +
           std::to_string(VK_API_VERSION_PATCH(version));
}

std::string DeviceCandidate::describe() const {
    std::string text = properties.deviceName;
    text += " [";
    if (driver.driverName[0]) text += std::string(driver.driverName) + ", ";
    text += "Vulkan " + api_version_string(properties.apiVersion) + "]";
    if (!unusable.empty()) text += " (unusable: " + unusable + ")";
    return text;
}

Instance::Instance(bool validation) : validation_(validation) {
    uint32_t layer_count = 0;
    vkEnumerateInstanceLayerProperties(&layer_count, nullptr);
    std::vector<VkLayerProperties> layers(layer_count);
    vkEnumerateInstanceLayerProperties(&layer_count, layers.data());
    const char* validation_layer = "VK_LAYER_KHRONOS_validation";
    bool have_validation = std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
        return std::strcmp(l.layerName, validation_layer) == 0;
    });
    if (validation && !have_validation)
        throw Error(
            "vulkan: PRISM_VULKAN_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed "
            "(apt-get install vulkan-validationlayers)");

    uint32_t extension_count = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &extension_count, nullptr);
    std::vector<VkExtensionProperties> extensions(extension_count);
    vkEnumerateInstanceExtensionProperties(nullptr, &extension_count, extensions.data());
    bool have_debug_utils = std::any_of(extensions.begin(), extensions.end(), [](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) == 0;
    });
    if (validation && !have_debug_utils)
        throw Error("vulkan: PRISM_VULKAN_VALIDATION=1 but the loader lacks " VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "prism";
    app.pEngineName = "prism";
    app.apiVersion = VK_API_VERSION_1_2;

    VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messenger_info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messenger_info.pfnUserCallback = debug_callback;

    std::vector<const char*> enabled_extensions;
    if (have_debug_utils) enabled_extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    info.enabledExtensionCount = uint32_t(enabled_extensions.size());
    info.ppEnabledExtensionNames = enabled_extensions.data();
    if (validation) {
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &validation_layer;
    }
    if (have_debug_utils) info.pNext = &messenger_info;  // also reports during vkCreateInstance itself
    VkResult result = vkCreateInstance(&info, nullptr, &instance_);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error(
            "vulkan: no Vulkan driver (VK_ERROR_INCOMPATIBLE_DRIVER): install a driver, e.g. mesa-vulkan-drivers");
    check(result, "vkCreateInstance");
    if (have_debug_utils) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (create) create(instance_, &messenger_info, nullptr, &messenger_);
    }
}

Instance::~Instance() {
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::vector<DeviceCandidate> Instance::devices() const {
    uint32_t count = 0;
    check(vkEnumeratePhysicalDevices(instance_, &count, nullptr), "vkEnumeratePhysicalDevices");
    std::vector<VkPhysicalDevice> handles(count);
    check(vkEnumeratePhysicalDevices(instance_, &count, handles.data()), "vkEnumeratePhysicalDevices");
    handles.resize(count);

    std::vector<DeviceCandidate> result;
    for (VkPhysicalDevice handle : handles) {
        DeviceCandidate d;
        d.handle = handle;
        vkGetPhysicalDeviceProperties(handle, &d.properties);
        if (d.properties.apiVersion >= VK_API_VERSION_1_2) {
            VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
            VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
            d.driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
            d.driver.pNext = &subgroup;
            properties2.pNext = &d.driver;
            vkGetPhysicalDeviceProperties2(handle, &properties2);
            d.driver.pNext = nullptr;
            // The stages take queue slots a subgroup at a time (kernels/compat/glsl.h, RT_QUEUE_RESERVE).
            const VkSubgroupFeatureFlags needed =
                VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT;
            if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
                (subgroup.supportedOperations & needed) != needed)
                d.unusable = "no subgroup arithmetic and ballot in compute shaders";
        } else {
            d.unusable = "Vulkan " + api_version_string(d.properties.apiVersion) + " < 1.2";
        }
        uint32_t family_count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(handle, &family_count, nullptr);
        std::vector<VkQueueFamilyProperties> families(family_count);
        vkGetPhysicalDeviceQueueFamilyProperties(handle, &family_count, families.data());
        // Prefer a compute queue with timestamps; a dedicated compute family (no graphics) when there is one.
        int best_score = -1;
        for (uint32_t f = 0; f < family_count; ++f) {
            if (!(families[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
            int score =
                (families[f].timestampValidBits > 0 ? 2 : 0) + (families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT ? 0 : 1);
            if (score > best_score) {
                best_score = score;
                d.compute_family = f;
            }
        }
        if (d.compute_family == UINT32_MAX && d.unusable.empty()) d.unusable = "no compute queue";
        d.transfer_family = transfer_only_family(families);
        if (d.unusable.empty() && d.properties.limits.maxPerStageDescriptorStorageBuffers < device_array_count)
            d.unusable = "fewer than " + std::to_string(device_array_count) + " storage buffers per stage";
        result.push_back(d);
    }
    return result;
}

DeviceCandidate Instance::select(const std::string& filter) const {
    std::vector<DeviceCandidate> all = devices();
    std::string list;
    for (const DeviceCandidate& d : all) list += (list.empty() ? "" : "; ") + d.describe();
    if (all.empty()) throw Error("Vulkan: no compute-capable device (no physical device found)");
    if (filter.empty()) {
        for (const DeviceCandidate& d : all)
            if (d.unusable.empty() && (d.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU ||
                                       d.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU))
                return d;
        for (const DeviceCandidate& d : all)
            if (d.unusable.empty()) return d;
        throw Error("Vulkan: no compute-capable device (found: " + list + ")");
    }
    // A number is the device's place in the list (`prism render --backend vulkan:all` names devices so).
    if (std::optional<size_t> index = device_index(filter)) {
        if (*index >= all.size()) throw Error("vulkan: no device " + filter + " (found: " + list + ")");
        if (!all[*index].unusable.empty()) throw Error("vulkan: device " + all[*index].describe());
        return all[*index];
    }
    for (const DeviceCandidate& d : all) {
        bool match = name_matches(d.properties.deviceName, filter) || name_matches(d.driver.driverName, filter);
        if (!match) continue;
        if (!d.unusable.empty()) throw Error("vulkan: device " + d.describe());
        return d;
    }
    throw Error("vulkan: no device matches '" + filter + "' (found: " + list + ")");
}

uint32_t transfer_only_family(std::span<const VkQueueFamilyProperties> families) {
    for (uint32_t f = 0; f < families.size(); ++f) {
        VkQueueFlags flags = families[f].queueFlags;
        if ((flags & VK_QUEUE_TRANSFER_BIT) && !(flags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT))) return f;
    }
    return UINT32_MAX;
}

std::vector<VkDeviceQueueCreateInfo> queue_create_infos(const DeviceCandidate& device, bool with_transfer) {
    // Read by vkCreateDevice after this returns, so it must outlive the call.
    static const float priority = 1.0f;
    std::vector<VkDeviceQueueCreateInfo> queues;
    for (uint32_t family : {device.compute_family, with_transfer ? device.transfer_family : UINT32_MAX}) {
        if (family == UINT32_MAX) continue;
        VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queue.queueFamilyIndex = family;
        queue.queueCount = 1;
        queue.pQueuePriorities = &priority;
        queues.push_back(queue);
    }
    return queues;
}

DeviceQueues get_device_queues(VkDevice device, const DeviceCandidate& candidate, bool with_transfer) {
    DeviceQueues queues;
    vkGetDeviceQueue(device, candidate.compute_family, 0, &queues.compute);
    if (with_transfer && candidate.transfer_family != UINT32_MAX)
        vkGetDeviceQueue(device, candidate.transfer_family, 0, &queues.transfer);
    return queues;
}

uint32_t find_memory_type(const VkPhysicalDeviceMemoryProperties& memory, uint32_t type_bits,
                          VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred,
                          VkMemoryPropertyFlags avoided) {
    uint32_t best = UINT32_MAX;
    int best_score = -1;
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
        VkMemoryPropertyFlags flags = memory.memoryTypes[i].propertyFlags;
        if (!(type_bits & (1u << i)) || (flags & required) != required) continue;
        int score = 2 * __builtin_popcount(flags & preferred) + (flags & avoided ? 0 : 1);
        if (score > best_score) {
            best_score = score;
            best = i;
        }
    }
    return best;
}

GridChoice choose_grid(const DeviceCandidate& device) {
    GridChoice grid;
    VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    VkPhysicalDeviceShaderSMBuiltinsPropertiesNV nv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_SM_BUILTINS_PROPERTIES_NV};
    VkPhysicalDeviceShaderCorePropertiesAMD amd{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_CORE_PROPERTIES_AMD};
    if (has_device_extension(device.handle, VK_NV_SHADER_SM_BUILTINS_EXTENSION_NAME)) {
        properties2.pNext = &nv;
        vkGetPhysicalDeviceProperties2(device.handle, &properties2);
        grid.compute_units = nv.shaderSMCount;
        grid.source = "SMs (VK_NV_shader_sm_builtins)";
    } else if (has_device_extension(device.handle, VK_AMD_SHADER_CORE_PROPERTIES_EXTENSION_NAME)) {
        properties2.pNext = &amd;
        vkGetPhysicalDeviceProperties2(device.handle, &properties2);
        grid.compute_units = amd.shaderEngineCount * amd.shaderArraysPerEngineCount * amd.computeUnitsPerShaderArray;
        grid.source = "CUs (VK_AMD_shader_core_properties)";
    } else if (device.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) {
        grid.compute_units = std::max(1u, std::thread::hardware_concurrency());
        grid.source = "host threads (CPU device)";
    }
    if (grid.compute_units == 0) {
        // No standard query: a mid-size GPU's figure, so the grid still fills the device with the stride loop.
        grid.compute_units = device.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU ? 64 : 16;
        grid.source = "default for the device type";
    }
    uint64_t groups = uint64_t(grid.compute_units) * kWorkGroupsPerComputeUnit;  // core/render/launch_config.h
    grid.groups = uint32_t(std::min<uint64_t>(groups, device.properties.limits.maxComputeWorkGroupCount[0]));
    return grid;
}

}  // namespace vk
}  // namespace prism
