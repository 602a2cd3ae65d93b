#include "backends/vulkan/vulkan_gl_interop.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <utility>

#include "core/util/error.h"

namespace prism::vk {
namespace {

std::string hex(const uint8_t* bytes, size_t n) {
    std::string text;
    char pair[3];
    for (size_t i = 0; i < n; ++i) {
        std::snprintf(pair, sizeof pair, "%02x", bytes[i]);
        text += pair;
    }
    return text;
}

constexpr VkBufferUsageFlags kSharedUsage = VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr VkExternalMemoryHandleTypeFlagBits kMemoryHandle = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
constexpr VkExternalSemaphoreHandleTypeFlagBits kSemaphoreHandle = VK_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_FD_BIT;
constexpr VkDeviceSize kGlSlackBytes = 4096;

class VulkanGlInterop final : public GlInterop {
public:
    VulkanGlInterop(VkDevice device, const DeviceCandidate& physical, const VkPhysicalDeviceMemoryProperties& memory,
                    ImageCopier& copier, const GlSharingPlan& plan)
        : device_(device), physical_(physical), memory_(memory), copier_(copier), plan_(plan) {
        get_memory_fd_ = reinterpret_cast<PFN_vkGetMemoryFdKHR>(vkGetDeviceProcAddr(device_, "vkGetMemoryFdKHR"));
        get_semaphore_fd_ =
            reinterpret_cast<PFN_vkGetSemaphoreFdKHR>(vkGetDeviceProcAddr(device_, "vkGetSemaphoreFdKHR"));
    }
    ~VulkanGlInterop() override { release(); }

    std::string name() const override { return "Vulkan-GL"; }
    std::string sync() const override {
        if (plan_.semaphores) return "shared semaphores (VK_KHR_external_semaphore_fd + GL_EXT_semaphore_fd)";
        return "fence waits, no shared semaphores (" + plan_.no_semaphores + ")";
    }
    bool device_owns_memory() const override { return true; }
    bool needs_gl_idle_before_copy() const override { return !plan_.semaphores; }

    ExportedBuffer export_buffer(size_t bytes) override {
        release();
        ExportedBuffer exported;
        try {
            exported = create_exported(bytes);
        } catch (...) {
            release();
            throw;
        }
        return exported;
    }

    void copy_image(size_t bytes) override {
        if (!buffer_) throw Error("vulkan: Vulkan-GL copy before the buffer was exported");
        if (bytes > bytes_)
            throw Error("vulkan: frame of " + std::to_string(bytes) + " bytes does not fit the shared buffer of " +
                        std::to_string(bytes_));
        // GL signals `released` after each read of the buffer; the first copy has nothing to wait for. Without
        // semaphores the host waits for GL here instead.
        if (!plan_.semaphores) wait_for_gl_idle();
        bool returned = copies_ > 0;
        copier_.copy_image_to(buffer_, bytes, returned, returned ? released_ : VK_NULL_HANDLE, ready_);
        ++copies_;
    }

private:
    ExportedBuffer create_exported(size_t bytes) {
        const std::string device_name = physical_.properties.deviceName;
        VkExternalMemoryBufferCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO};
        external.handleTypes = kMemoryHandle;
        VkBufferCreateInfo buffer_info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        buffer_info.pNext = &external;
        // GL may want the memory to be larger than the buffer it places in it: llvmpipe over-allocates buffers by
        // 48 bytes for its block reads and refuses memory without that room (GL_OUT_OF_MEMORY). A page covers it.
        buffer_info.size = VkDeviceSize(bytes) + kGlSlackBytes;
        buffer_info.usage = kSharedUsage;
        buffer_info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        check(vkCreateBuffer(device_, &buffer_info, nullptr, &buffer_), "vkCreateBuffer (exportable)");

        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(device_, buffer_, &requirements);
        uint32_t type = find_memory_type(memory_, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0,
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
        if (type == UINT32_MAX)
            throw Error("vulkan: no device-local memory type for the shared buffer on " + device_name);
        // A dedicated allocation: what drivers prefer (or require) for exported memory, and GL is told the same.
        VkMemoryDedicatedAllocateInfo dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO};
        dedicated.buffer = buffer_;
        VkExportMemoryAllocateInfo export_info{VK_STRUCTURE_TYPE_EXPORT_MEMORY_ALLOCATE_INFO};
        export_info.pNext = &dedicated;
        export_info.handleTypes = kMemoryHandle;
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.pNext = &export_info;
        alloc.allocationSize = requirements.size;
        alloc.memoryTypeIndex = type;
        check(vkAllocateMemory(device_, &alloc, nullptr, &memory_handle_), "vkAllocateMemory (exportable)");
        check(vkBindBufferMemory(device_, buffer_, memory_handle_, 0), "vkBindBufferMemory (exportable)");
        bytes_ = bytes;

        ExportedBuffer exported;
        exported.allocation_size = requirements.size;
        exported.dedicated = true;
        if (!get_memory_fd_) throw Error("vulkan: vkGetMemoryFdKHR missing on " + device_name);
        VkMemoryGetFdInfoKHR fd_info{VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR};
        fd_info.memory = memory_handle_;
        fd_info.handleType = kMemoryHandle;
        check(get_memory_fd_(device_, &fd_info, &exported.memory_fd), "vkGetMemoryFdKHR");
        if (plan_.semaphores) {
            try {
                ready_ = create_semaphore(exported.ready_semaphore_fd);
                released_ = create_semaphore(exported.released_semaphore_fd);
            } catch (...) {
                for (int fd : {exported.memory_fd, exported.ready_semaphore_fd, exported.released_semaphore_fd})
                    if (fd >= 0) ::close(fd);
                throw;
            }
        }
        copies_ = 0;
        return exported;
    }

    VkSemaphore create_semaphore(int& fd) {
        VkExportSemaphoreCreateInfo export_info{VK_STRUCTURE_TYPE_EXPORT_SEMAPHORE_CREATE_INFO};
        export_info.handleTypes = kSemaphoreHandle;
        VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        info.pNext = &export_info;
        VkSemaphore semaphore = VK_NULL_HANDLE;
        check(vkCreateSemaphore(device_, &info, nullptr, &semaphore), "vkCreateSemaphore (exportable)");
        if (!get_semaphore_fd_) {
            vkDestroySemaphore(device_, semaphore, nullptr);
            throw Error("vulkan: vkGetSemaphoreFdKHR missing");
        }
        VkSemaphoreGetFdInfoKHR fd_info{VK_STRUCTURE_TYPE_SEMAPHORE_GET_FD_INFO_KHR};
        fd_info.semaphore = semaphore;
        fd_info.handleType = kSemaphoreHandle;
        VkResult result = get_semaphore_fd_(device_, &fd_info, &fd);
        if (result != VK_SUCCESS) {
            vkDestroySemaphore(device_, semaphore, nullptr);
            check(result, "vkGetSemaphoreFdKHR");
        }
        return semaphore;
    }

    void release() {
        if (!buffer_ && !memory_handle_ && !ready_ && !released_) return;
        vkDeviceWaitIdle(device_);  // no submitted copy may still use them
        if (ready_) vkDestroySemaphore(device_, std::exchange(ready_, VK_NULL_HANDLE), nullptr);
        if (released_) vkDestroySemaphore(device_, std::exchange(released_, VK_NULL_HANDLE), nullptr);
        if (buffer_) vkDestroyBuffer(device_, std::exchange(buffer_, VK_NULL_HANDLE), nullptr);
        // GL holds its own reference to the memory through the imported fd.
        if (memory_handle_) vkFreeMemory(device_, std::exchange(memory_handle_, VK_NULL_HANDLE), nullptr);
        bytes_ = 0;
    }

    VkDevice device_;
    const DeviceCandidate& physical_;
    const VkPhysicalDeviceMemoryProperties& memory_;
    ImageCopier& copier_;
    GlSharingPlan plan_;
    PFN_vkGetMemoryFdKHR get_memory_fd_ = nullptr;
    PFN_vkGetSemaphoreFdKHR get_semaphore_fd_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_handle_ = VK_NULL_HANDLE;
    VkSemaphore ready_ = VK_NULL_HANDLE;     // device -> GL: the copy is done
    VkSemaphore released_ = VK_NULL_HANDLE;  // GL -> device: GL has read the buffer
    size_t bytes_ = 0;
    uint64_t copies_ = 0;
};

}  // namespace

GlSharingPlan plan_gl_sharing(const DeviceCandidate& device, const GlContextHandles& gl) {
    GlSharingPlan plan;
    const std::string name = device.properties.deviceName;
    if (!gl.memory_object_fd) {
        plan.reason = "GL (" + gl.renderer + ") has no GL_EXT_memory_object_fd";
        return plan;
    }
    if (!has_device_extension(device.handle, VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME)) {
        plan.reason = name + " has no " VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME;
        return plan;
    }
    VkPhysicalDeviceIDProperties ids{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &ids;
    vkGetPhysicalDeviceProperties2(device.handle, &properties);
    if (!std::equal(gl.device_uuid.begin(), gl.device_uuid.end(), ids.deviceUUID) ||
        !std::equal(gl.driver_uuid.begin(), gl.driver_uuid.end(), ids.driverUUID)) {
        plan.reason = "GL (" + gl.renderer + ") runs on another device or driver than " + name +
                      " (device/driver UUID " + hex(gl.device_uuid.data(), 16) + "/" + hex(gl.driver_uuid.data(), 16) +
                      " vs " + hex(ids.deviceUUID, VK_UUID_SIZE) + "/" + hex(ids.driverUUID, VK_UUID_SIZE) + ")";
        return plan;
    }
    VkPhysicalDeviceExternalBufferInfo buffer_info{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_BUFFER_INFO};
    buffer_info.usage = kSharedUsage;
    buffer_info.handleType = kMemoryHandle;
    VkExternalBufferProperties buffer_properties{VK_STRUCTURE_TYPE_EXTERNAL_BUFFER_PROPERTIES};
    vkGetPhysicalDeviceExternalBufferProperties(device.handle, &buffer_info, &buffer_properties);
    if (!(buffer_properties.externalMemoryProperties.externalMemoryFeatures &
          VK_EXTERNAL_MEMORY_FEATURE_EXPORTABLE_BIT)) {
        plan.reason = name + " cannot export buffer memory as an opaque fd";
        return plan;
    }
    plan.extensions.push_back(VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME);

    VkPhysicalDeviceExternalSemaphoreInfo semaphore_info{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_SEMAPHORE_INFO};
    semaphore_info.handleType = kSemaphoreHandle;
    VkExternalSemaphoreProperties semaphore_properties{VK_STRUCTURE_TYPE_EXTERNAL_SEMAPHORE_PROPERTIES};
    vkGetPhysicalDeviceExternalSemaphoreProperties(device.handle, &semaphore_info, &semaphore_properties);
    if (!gl.semaphore_fd) {
        plan.no_semaphores = "GL has no GL_EXT_semaphore_fd";
    } else if (!has_device_extension(device.handle, VK_KHR_EXTERNAL_SEMAPHORE_FD_EXTENSION_NAME) ||
               !(semaphore_properties.externalSemaphoreFeatures & VK_EXTERNAL_SEMAPHORE_FEATURE_EXPORTABLE_BIT)) {
        plan.no_semaphores = name + " cannot export semaphores as opaque fds";
    } else {
        plan.semaphores = true;
        plan.extensions.push_back(VK_KHR_EXTERNAL_SEMAPHORE_FD_EXTENSION_NAME);
    }
    return plan;
}

std::unique_ptr<GlInterop> create_gl_interop(VkDevice device, const DeviceCandidate& physical,
                                             const VkPhysicalDeviceMemoryProperties& memory, ImageCopier& copier,
                                             const GlSharingPlan& plan) {
    return std::make_unique<VulkanGlInterop>(device, physical, memory, copier, plan);
}

}  // namespace prism::vk
