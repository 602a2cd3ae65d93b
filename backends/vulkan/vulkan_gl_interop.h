// The Vulkan-GL display path: a buffer in exportable device memory (VK_KHR_external_memory_fd, dedicated
// allocation, opaque fd) that GL imports as the buffer it draws the frame from (GL_EXT_memory_object_fd), the frame
// copied into it on the device at the end of each shown frame, and two exported semaphores
// (VK_KHR_external_semaphore_fd + GL_EXT_semaphore_fd) ordering the copy and GL's read where both sides offer them;
// otherwise the frame's fence wait, plus a GL fence before the next frame's copy, is the sync.
#pragma once

#include <vulkan/vulkan.h>

#include <memory>
#include <string>
#include <vector>

#include "backends/vulkan/vulkan_context.h"
#include "core/render/gl_interop.h"

namespace prism::vk {

// Decided before vkCreateDevice, since the extensions must be enabled there.
struct GlSharingPlan {
    std::string reason;                   // non-empty: no Vulkan-GL path, and why
    std::vector<const char*> extensions;  // device extensions to enable
    bool semaphores = false;              // shared semaphores on both sides
    std::string no_semaphores;            // why not, when they are not
};
// Checks GL_EXT_memory_object_fd, VK_KHR_external_memory_fd, that GL and `device` are the same device and driver
// (VkPhysicalDeviceIDProperties against GL_DEVICE_UUID_EXT / GL_DRIVER_UUID_EXT: memory from another is useless
// to GL), that an opaque-fd buffer can be exported, and whether semaphores can be shared too.
GlSharingPlan plan_gl_sharing(const DeviceCandidate& device, const GlContextHandles& gl);

// The backend's side of a frame copy: its `image` array into `target`, recorded after the stages enqueued so far,
// in the frame's own submission (whose fence the frame's read-back waits on). `wait`/`signal`: semaphores for that
// submission, or VK_NULL_HANDLE. `acquire`: the buffer comes back from GL (a queue family ownership transfer from
// VK_QUEUE_FAMILY_EXTERNAL first).
class ImageCopier {
public:
    virtual ~ImageCopier() = default;
    virtual void copy_image_to(VkBuffer target, VkDeviceSize bytes, bool acquire, VkSemaphore wait,
                               VkSemaphore signal) = 0;
};

std::unique_ptr<GlInterop> create_gl_interop(VkDevice device, const DeviceCandidate& physical,
                                             const VkPhysicalDeviceMemoryProperties& memory, ImageCopier& copier,
                                             const GlSharingPlan& plan);

}  // namespace prism::vk
