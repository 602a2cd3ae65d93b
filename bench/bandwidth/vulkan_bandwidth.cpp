// Vulkan: every physical device. There is no pageable transfer in Vulkan: "pinned" copies go between a mapped
// host-visible staging buffer and a device-local buffer with one vkCmdCopyBuffer (the readback staging buffer is
// host-cached); "pageable" copies add the memcpy between the application's malloc'd memory and that staging buffer,
// as a driver does internally, so only wall time is meaningful for them. Every copy command is measured on the
// compute queue and again on the transfer-only queue where the device has one: which is faster differs by driver,
// and users choose. Device timer: vkCmdWriteTimestamp around the copy or dispatch.
// PRISM_VULKAN_STAGING=host (or host-4k) stages the pinned copies through the application's own memory instead,
// imported with VK_EXT_external_memory_host, with transparent huge pages asked for (or refused): the pinned copy
// then reads the kind of memory CUDA's cudaHostRegister pins, and the report says how much of it the kernel backed
// with huge pages. PRISM_VULKAN_COPY_REGIONS=n makes each copy command n regions of equal size instead of one.
#include <sys/mman.h>
#include <vulkan/vulkan.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "backends/vulkan/vulkan_context.h"
#include "bench/bandwidth/api_runners.h"
#include "bench/bandwidth/copy_device.h"
#include "bench/bandwidth/pci_link.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bandwidth/sweep.h"
#include "core/util/error.h"
#include "kernels/bandwidth_copy.h"
#include "spirv/bandwidth_copy.h"

namespace prism::bandwidth {
namespace {

using Clock = std::chrono::steady_clock;
using vk::check;

bool is_out_of_memory(VkResult result) {
    return result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY;
}

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    std::byte* mapped = nullptr;
    bool coherent = true;
    size_t imported_bytes = 0;  // > 0: `mapped` is the application's mmap imported into `memory`
};

constexpr size_t kHugePage = size_t(2) << 20;

// KiB of the mapping that starts at `address` the kernel backs with transparent huge pages (/proc/self/smaps).
size_t huge_page_kib(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool in_mapping = false;
    while (std::getline(smaps, line)) {
        uintptr_t start = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> start >> dash && dash == '-') {
            in_mapping = start == reinterpret_cast<uintptr_t>(address);
        } else if (in_mapping && line.rfind("AnonHugePages:", 0) == 0) {
            return std::stoul(line.substr(14));
        }
    }
    return 0;
}

// The instance, device list, queue families, memory-type choice and error text are the backend's
// (backends/vulkan/vulkan_context.h); the staging buffers and copy commands are this test's own.
// One recorded command buffer plus the queue it runs on; re-recorded for each size.
struct Command {
    VkCommandBuffer buffer = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    bool timestamps = false;
    uint64_t timestamp_mask = 0;  // the queue family's valid timestamp bits
};

// The copy commands of one queue.
struct CopyCommands {
    Command upload, download, copy;
};

class VulkanDevice final : public CopyDevice {
public:
    VulkanDevice(const vk::DeviceCandidate& candidate, const std::string& staging, unsigned copy_regions)
        : candidate_(candidate),
          physical_(candidate.handle),
          properties_(candidate.properties),
          driver_(candidate.driver),
          has_transfer_(candidate.transfer_family != UINT32_MAX),
          families_{candidate.compute_family, candidate.transfer_family},
          import_host_(staging == "host" || staging == "host-4k"),
          huge_pages_(staging == "host"),
          copy_regions_(copy_regions) {
        read_properties(staging == "cached");
        if (candidate.compute_family == UINT32_MAX)
            throw Error(std::string("vulkan ") + properties_.deviceName + ": no compute queue");
        create_device();
        create_kernel();
    }
    ~VulkanDevice() override {
        if (!device_) return;
        vkDeviceWaitIdle(device_);
        release();
        vkDestroyFence(device_, fence_, nullptr);
        vkDestroyQueryPool(device_, queries_, nullptr);
        vkDestroyPipeline(device_, pipeline_, nullptr);
        vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
        vkDestroyDescriptorPool(device_, descriptor_pool_, nullptr);
        vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
        vkDestroyShaderModule(device_, shader_, nullptr);
        vkDestroyCommandPool(device_, compute_pool_, nullptr);
        if (transfer_pool_) vkDestroyCommandPool(device_, transfer_pool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }

    DeviceResult describe() const override {
        DeviceResult result;
        result.api = "vulkan";
        result.device = properties_.deviceName;
        result.platform = driver_.driverName;
        result.driver = std::string(driver_.driverName) + " " + driver_.driverInfo;
        result.api_version = "Vulkan " + vk::api_version_string(properties_.apiVersion);
        result.pci_address = pci_address_;
        for (uint32_t i = 0; i < memory_.memoryHeapCount; ++i)
            if (memory_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
                result.device_memory = std::max<size_t>(result.device_memory, memory_.memoryHeaps[i].size);
        std::string compute = "compute queue family " + std::to_string(candidate_.compute_family);
        result.details.push_back(has_transfer_
                                     ? "H2D, D2H, D2D copy: vkCmdCopyBuffer on the " + compute +
                                           " [compute] and on the transfer-only queue family " +
                                           std::to_string(candidate_.transfer_family) + " [transfer]"
                                     : "H2D, D2H, D2D copy: vkCmdCopyBuffer on the " + compute +
                                           " [compute]; no transfer-only queue family, so no [transfer] rows");
        if (copy_regions_ > 1)
            result.details.push_back("each vkCmdCopyBuffer copies up to " + std::to_string(copy_regions_) +
                                     " regions of equal size, each 256 bytes or more (PRISM_VULKAN_COPY_REGIONS)");
        result.details.push_back("D2D kernel: dispatched on the compute queue");
        if (import_host_) {
            result.details.push_back(std::string("pinned H2D and D2H through the application's memory imported with "
                                                 "VK_EXT_external_memory_host, transparent huge pages ") +
                                     (huge_pages_ ? "asked for" : "refused") + "; " + huge_page_report_ +
                                     " (PRISM_VULKAN_STAGING)");
        } else {
            result.details.push_back(
                std::string("pinned H2D from ") +
                (memory_.memoryTypes[upload_].propertyFlags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT ? "host-cached"
                                                                                                 : "uncached") +
                " system memory, D2H into " +
                (memory_.memoryTypes[readback_].propertyFlags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT ? "host-cached"
                                                                                                   : "uncached") +
                " (PRISM_VULKAN_STAGING picks the upload's)");
        }
        result.details.push_back("pageable: memcpy to/from the staging buffer plus the copy; wall time only");
        if (has_transfer_ && !transfer_copies_.copy.timestamps)
            result.details.push_back("the transfer queue has no timestamps: wall time only there");
        if (!host_query_reset_) result.details.push_back("no hostQueryReset: wall time only");
        return result;
    }

    std::string cannot_fit(size_t bytes) const override {
        if (bytes > max_allocation_)
            return "larger than maxMemoryAllocationSize (" + format_size(max_allocation_) + ")";
        std::map<uint32_t, size_t> need;  // heap -> bytes
        need[heap_of(device_local_)] += 2 * bytes;
        need[heap_of(upload_)] += bytes;
        need[heap_of(readback_)] += bytes;
        for (auto [heap, bytes_needed] : need)
            if (bytes_needed > memory_.memoryHeaps[heap].size)
                return "needs " + format_size(bytes_needed) + " in memory heap " + std::to_string(heap) + " of " +
                       format_size(memory_.memoryHeaps[heap].size);
        return "";
    }

    std::string kernel_cannot_fit(size_t bytes) const override {
        if (!pipeline_) return "the compute pipeline could not be created";
        if (bytes > properties_.limits.maxStorageBufferRange)
            return "larger than maxStorageBufferRange (" + format_size(properties_.limits.maxStorageBufferRange) + ")";
        return "";
    }

    void allocate(size_t bytes, std::byte* pageable) override {
        bytes_ = bytes;
        pageable_ = pageable;
        const VkBufferUsageFlags copy = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        buffer_a_ = create_buffer(copy | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, device_local_, "device buffer A");
        buffer_b_ = create_buffer(copy | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, device_local_, "device buffer B");
        if (import_host_) {
            upload_staging_ = import_buffer(copy, "upload staging buffer");
            readback_staging_ = import_buffer(copy, "readback staging buffer");
            size_t kib = huge_page_kib(upload_staging_.mapped) + huge_page_kib(readback_staging_.mapped);
            huge_page_report_ =
                std::to_string(kib / 1024) + " of " +
                std::to_string((upload_staging_.imported_bytes + readback_staging_.imported_bytes) >> 20) +
                " MiB of the last size's two staging buffers in huge pages";
        } else {
            upload_staging_ = create_buffer(copy, upload_, "upload staging buffer");
            readback_staging_ = create_buffer(copy, readback_, "readback staging buffer");
        }
        record_all();
    }

    void release() override {
        if (!device_) return;
        vkDeviceWaitIdle(device_);
        for (Buffer* buffer : {&buffer_a_, &buffer_b_, &upload_staging_, &readback_staging_}) {
            if (buffer->mapped && !buffer->imported_bytes) vkUnmapMemory(device_, buffer->memory);
            vkDestroyBuffer(device_, buffer->buffer, nullptr);
            vkFreeMemory(device_, buffer->memory, nullptr);
            if (buffer->imported_bytes) munmap(buffer->mapped, buffer->imported_bytes);
            *buffer = Buffer{};
        }
    }

    std::vector<std::string> copy_queues() const override {
        if (has_transfer_) return {"compute", "transfer"};
        return {"compute"};
    }
    void use_copy_queue(const std::string& queue) override {
        copies_ = queue == "transfer" ? &transfer_copies_ : &compute_copies_;
    }

    std::byte* pinned_upload() override { return upload_staging_.mapped; }
    std::byte* pinned_download() override { return readback_staging_.mapped; }

    Timed upload(Memory host) override {
        auto start = Clock::now();
        if (host == Memory::Pageable) {
            std::memcpy(upload_staging_.mapped, pageable_, bytes_);
            flush(upload_staging_);
        }
        std::optional<double> device_seconds = submit(copies_->upload);
        return finish(start, host == Memory::Pinned ? device_seconds : std::nullopt);
    }

    Timed download(Memory host) override {
        auto start = Clock::now();
        std::optional<double> device_seconds = submit(copies_->download);
        invalidate(readback_staging_);
        if (host == Memory::Pageable) std::memcpy(pageable_, readback_staging_.mapped, bytes_);
        return finish(start, host == Memory::Pinned ? device_seconds : std::nullopt);
    }

    Timed copy_buffer() override {
        auto start = Clock::now();
        std::optional<double> device_seconds = submit(copies_->copy);
        return finish(start, device_seconds);
    }

    Timed copy_kernel() override {
        auto start = Clock::now();
        std::optional<double> device_seconds = submit(kernel_command_);
        return finish(start, device_seconds);
    }

    void clear_destination() override { submit(clear_command_); }

    void read_destination() override {
        submit(read_destination_command_);
        invalidate(readback_staging_);
        std::memcpy(pageable_, readback_staging_.mapped, bytes_);
    }

private:
    void read_properties(bool cached_upload) {
        if (properties_.apiVersion < VK_API_VERSION_1_2)
            throw Error(std::string("vulkan ") + properties_.deviceName + ": device supports only Vulkan " +
                        vk::api_version_string(properties_.apiVersion) + ", 1.2 needed");
        VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
        VkPhysicalDevicePCIBusInfoPropertiesEXT pci{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PCI_BUS_INFO_PROPERTIES_EXT};
        VkPhysicalDeviceExternalMemoryHostPropertiesEXT host{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_MEMORY_HOST_PROPERTIES_EXT};
        properties.pNext = &maintenance3;
        bool has_pci = vk::has_device_extension(physical_, VK_EXT_PCI_BUS_INFO_EXTENSION_NAME);
        if (has_pci) maintenance3.pNext = &pci;
        if (import_host_) {
            if (!vk::has_device_extension(physical_, VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME))
                throw Error(std::string("vulkan ") + properties_.deviceName +
                            ": PRISM_VULKAN_STAGING=host needs VK_EXT_external_memory_host, which it lacks");
            host.pNext = maintenance3.pNext;
            maintenance3.pNext = &host;
        }
        vkGetPhysicalDeviceProperties2(physical_, &properties);
        import_alignment_ = std::max<size_t>(host.minImportedHostPointerAlignment, kHugePage);
        max_allocation_ = maintenance3.maxMemoryAllocationSize;
        if (has_pci) pci_address_ = pci_address(pci.pciDomain, pci.pciBus, pci.pciDevice, pci.pciFunction);
        vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
        const uint32_t any = ~0u;
        device_local_ = vk::find_memory_type(memory_, any, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0,
                                             VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
        // Staging in system memory (not device-local BAR memory): what crosses the link is what we time. The upload
        // buffer is the uncached (write-combined) kind an application writes once, unless PRISM_VULKAN_STAGING=cached
        // asks for the cached kind the readback buffer uses (docs/bandwidth.md measured both).
        upload_ = cached_upload
                      ? vk::find_memory_type(memory_, any, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                             VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                             VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
                      : vk::find_memory_type(memory_, any, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                             VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                             VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
        readback_ = vk::find_memory_type(memory_, any, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                         VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        if (device_local_ == UINT32_MAX || upload_ == UINT32_MAX || readback_ == UINT32_MAX)
            throw Error(std::string("vulkan ") + properties_.deviceName +
                        ": no device-local or host-visible memory type");
    }

    uint32_t heap_of(uint32_t type) const { return memory_.memoryTypes[type].heapIndex; }

    static uint64_t mask(uint32_t bits) { return bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1; }

    void create_device() {
        VkPhysicalDeviceVulkan12Features supported12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &supported12};
        vkGetPhysicalDeviceFeatures2(physical_, &supported);
        host_query_reset_ = supported12.hostQueryReset;
        VkPhysicalDeviceVulkan12Features enabled12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        enabled12.hostQueryReset = supported12.hostQueryReset;

        std::vector<VkDeviceQueueCreateInfo> queues = vk::queue_create_infos(candidate_, true);
        VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &enabled12};
        info.queueCreateInfoCount = static_cast<uint32_t>(queues.size());
        info.pQueueCreateInfos = queues.data();
        const char* import_extension = VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME;
        if (import_host_) {
            info.enabledExtensionCount = 1;
            info.ppEnabledExtensionNames = &import_extension;
        }
        check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
        if (import_host_) {
            host_pointer_properties_ = reinterpret_cast<PFN_vkGetMemoryHostPointerPropertiesEXT>(
                vkGetDeviceProcAddr(device_, "vkGetMemoryHostPointerPropertiesEXT"));
            if (!host_pointer_properties_)
                throw Error(std::string("vulkan ") + properties_.deviceName +
                            ": no vkGetMemoryHostPointerPropertiesEXT");
        }
        vk::DeviceQueues queue = vk::get_device_queues(device_, candidate_, true);

        uint32_t count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
        std::vector<VkQueueFamilyProperties> families(count);
        vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
        compute_pool_ = create_pool(candidate_.compute_family);
        uint32_t compute_bits = families[candidate_.compute_family].timestampValidBits;
        compute_copies_ = copy_commands(compute_pool_, queue.compute, compute_bits);
        if (has_transfer_) {
            transfer_pool_ = create_pool(candidate_.transfer_family);
            uint32_t transfer_bits = families[candidate_.transfer_family].timestampValidBits;
            transfer_copies_ = copy_commands(transfer_pool_, queue.transfer, transfer_bits);
        }
        kernel_command_ = command(compute_pool_, queue.compute, compute_bits);
        clear_command_ = command(compute_pool_, queue.compute, 0);
        read_destination_command_ = command(compute_pool_, queue.compute, 0);

        VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        query.queryType = VK_QUERY_TYPE_TIMESTAMP;
        query.queryCount = 2;
        check(vkCreateQueryPool(device_, &query, nullptr, &queries_), "vkCreateQueryPool");
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        check(vkCreateFence(device_, &fence, nullptr, &fence_), "vkCreateFence");
    }

    VkCommandPool create_pool(uint32_t family) {
        VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        info.queueFamilyIndex = family;
        VkCommandPool pool = VK_NULL_HANDLE;
        check(vkCreateCommandPool(device_, &info, nullptr, &pool), "vkCreateCommandPool");
        return pool;
    }

    CopyCommands copy_commands(VkCommandPool pool, VkQueue queue, uint32_t timestamp_bits) {
        return {command(pool, queue, timestamp_bits), command(pool, queue, timestamp_bits),
                command(pool, queue, timestamp_bits)};
    }

    // timestamp_bits 0: untimed (the queue family has no timestamps, or the command needs none).
    Command command(VkCommandPool pool, VkQueue queue, uint32_t timestamp_bits) {
        VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        info.commandPool = pool;
        info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        info.commandBufferCount = 1;
        Command result{VK_NULL_HANDLE, queue, timestamp_bits > 0 && host_query_reset_, mask(timestamp_bits)};
        check(vkAllocateCommandBuffers(device_, &info, &result.buffer), "vkAllocateCommandBuffers");
        return result;
    }

    void create_kernel() {
        VkShaderModuleCreateInfo module{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        module.codeSize = prism::spirv::bandwidth_copy_words * 4;
        module.pCode = prism::spirv::bandwidth_copy;
        check(vkCreateShaderModule(device_, &module, nullptr, &shader_), "vkCreateShaderModule");
        VkDescriptorSetLayoutBinding bindings[2]{};
        for (uint32_t i = 0; i < 2; ++i) {
            bindings[i].binding = i;
            bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            bindings[i].descriptorCount = 1;
            bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
        }
        VkDescriptorSetLayoutCreateInfo layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        layout.bindingCount = 2;
        layout.pBindings = bindings;
        check(vkCreateDescriptorSetLayout(device_, &layout, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");
        VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(uint32_t)};
        VkPipelineLayoutCreateInfo pipeline_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pipeline_layout.setLayoutCount = 1;
        pipeline_layout.pSetLayouts = &set_layout_;
        pipeline_layout.pushConstantRangeCount = 1;
        pipeline_layout.pPushConstantRanges = &push;
        check(vkCreatePipelineLayout(device_, &pipeline_layout, nullptr, &pipeline_layout_), "vkCreatePipelineLayout");
        VkComputePipelineCreateInfo pipeline{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipeline.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipeline.stage.module = shader_;
        pipeline.stage.pName = "main";
        pipeline.layout = pipeline_layout_;
        if (vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_) != VK_SUCCESS)
            pipeline_ = VK_NULL_HANDLE;
        VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
        VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pool.maxSets = 1;
        pool.poolSizeCount = 1;
        pool.pPoolSizes = &pool_size;
        check(vkCreateDescriptorPool(device_, &pool, nullptr, &descriptor_pool_), "vkCreateDescriptorPool");
        VkDescriptorSetAllocateInfo set{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        set.descriptorPool = descriptor_pool_;
        set.descriptorSetCount = 1;
        set.pSetLayouts = &set_layout_;
        check(vkAllocateDescriptorSets(device_, &set, &descriptor_set_), "vkAllocateDescriptorSets");
    }

    // A staging buffer over an anonymous mapping of the application's, imported (VK_EXT_external_memory_host):
    // the driver pins the pages it is given. Rounded up to 2 MiB (and the device's import alignment), so that
    // transparent huge pages can back all of it when asked for.
    Buffer import_buffer(VkBufferUsageFlags usage, const char* what) {
        Buffer result;
        size_t bytes = (bytes_ + import_alignment_ - 1) / import_alignment_ * import_alignment_;
        // One alignment more reserved, the unused head and tail returned: mmap itself aligns to 4 KiB only.
        size_t reserved = bytes + import_alignment_;
        void* raw = mmap(nullptr, reserved, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) throw SizeSkipped(std::string("out of host memory for ") + what);
        uintptr_t begin = reinterpret_cast<uintptr_t>(raw);
        uintptr_t aligned = (begin + import_alignment_ - 1) / import_alignment_ * import_alignment_;
        if (aligned > begin) munmap(raw, aligned - begin);
        if (aligned + bytes < begin + reserved)
            munmap(reinterpret_cast<void*>(aligned + bytes), begin + reserved - aligned - bytes);
        result.mapped = reinterpret_cast<std::byte*>(aligned);
        result.imported_bytes = bytes;
        madvise(result.mapped, bytes, huge_pages_ ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
        std::memset(result.mapped, 0, bytes);  // fault every page in before the driver pins them

        VkMemoryHostPointerPropertiesEXT pointer{VK_STRUCTURE_TYPE_MEMORY_HOST_POINTER_PROPERTIES_EXT};
        VkResult status = host_pointer_properties_(device_, VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT,
                                                   result.mapped, &pointer);
        if (status != VK_SUCCESS) {
            munmap(result.mapped, bytes);
            check(status, "vkGetMemoryHostPointerPropertiesEXT");
        }
        uint32_t type = vk::find_memory_type(memory_, pointer.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                             VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0);
        if (type == UINT32_MAX) type = vk::find_memory_type(memory_, pointer.memoryTypeBits, 0, 0, 0);
        if (type == UINT32_MAX) {
            munmap(result.mapped, bytes);
            throw Error(std::string("vulkan ") + properties_.deviceName + ": no memory type imports host memory");
        }
        result.coherent = memory_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

        VkExternalMemoryBufferCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO};
        external.handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT;
        VkBufferCreateInfo info = buffer_info(usage);
        info.pNext = &external;
        status = vkCreateBuffer(device_, &info, nullptr, &result.buffer);
        if (status != VK_SUCCESS) {
            munmap(result.mapped, bytes);
            if (is_out_of_memory(status)) throw SizeSkipped(std::string("out of memory for ") + what);
            check(status, "vkCreateBuffer");
        }
        VkImportMemoryHostPointerInfoEXT import{VK_STRUCTURE_TYPE_IMPORT_MEMORY_HOST_POINTER_INFO_EXT};
        import.handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT;
        import.pHostPointer = result.mapped;
        VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &import};
        allocate.allocationSize = bytes;
        allocate.memoryTypeIndex = type;
        status = vkAllocateMemory(device_, &allocate, nullptr, &result.memory);
        if (status == VK_SUCCESS) status = vkBindBufferMemory(device_, result.buffer, result.memory, 0);
        if (status != VK_SUCCESS) {
            vkDestroyBuffer(device_, result.buffer, nullptr);
            if (result.memory) vkFreeMemory(device_, result.memory, nullptr);
            munmap(result.mapped, bytes);
            if (is_out_of_memory(status)) throw SizeSkipped(std::string("out of memory importing ") + what);
            check(status, "importing host memory");
        }
        return result;
    }

    // A buffer of the measured size that both queues use.
    VkBufferCreateInfo buffer_info(VkBufferUsageFlags usage) const {
        VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        info.size = bytes_;
        info.usage = usage;
        // Concurrent sharing spares queue-family ownership transfers; buffers have no compressed layout to lose.
        info.sharingMode = has_transfer_ ? VK_SHARING_MODE_CONCURRENT : VK_SHARING_MODE_EXCLUSIVE;
        info.queueFamilyIndexCount = has_transfer_ ? 2 : 0;
        info.pQueueFamilyIndices = has_transfer_ ? families_ : nullptr;
        return info;
    }

    Buffer create_buffer(VkBufferUsageFlags usage, uint32_t memory_type, const char* what) {
        Buffer result;
        VkBufferCreateInfo info = buffer_info(usage);
        VkResult status = vkCreateBuffer(device_, &info, nullptr, &result.buffer);
        if (is_out_of_memory(status)) throw SizeSkipped(std::string("out of memory for ") + what);
        check(status, "vkCreateBuffer");
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(device_, result.buffer, &requirements);
        if (!(requirements.memoryTypeBits & (1u << memory_type))) {
            vkDestroyBuffer(device_, result.buffer, nullptr);
            throw Error(std::string("vulkan ") + properties_.deviceName + ": " + what +
                        " cannot use the chosen memory type");
        }
        VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        allocate.allocationSize = requirements.size;
        allocate.memoryTypeIndex = memory_type;
        status = vkAllocateMemory(device_, &allocate, nullptr, &result.memory);
        if (status != VK_SUCCESS) {
            vkDestroyBuffer(device_, result.buffer, nullptr);
            if (is_out_of_memory(status)) throw SizeSkipped(std::string("out of memory for ") + what);
            check(status, "vkAllocateMemory");
        }
        check(vkBindBufferMemory(device_, result.buffer, result.memory, 0), "vkBindBufferMemory");
        VkMemoryPropertyFlags flags = memory_.memoryTypes[memory_type].propertyFlags;
        if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
            void* mapped = nullptr;
            check(vkMapMemory(device_, result.memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
            result.mapped = static_cast<std::byte*>(mapped);
            result.coherent = flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        }
        return result;
    }

    // The regions of one copy of bytes_: one (the default), or PRISM_VULKAN_COPY_REGIONS pieces of equal size, each
    // a multiple of 256 bytes but the last.
    std::vector<VkBufferCopy> copy_regions() const {
        VkDeviceSize piece = (bytes_ / copy_regions_ + 255) / 256 * 256;
        if (copy_regions_ == 1 || piece == 0) return {VkBufferCopy{0, 0, bytes_}};
        std::vector<VkBufferCopy> regions;
        for (VkDeviceSize at = 0; at < bytes_; at += piece) regions.push_back({at, at, std::min(piece, bytes_ - at)});
        return regions;
    }

    // Records the per-size command buffers. A transfer is one vkCmdCopyBuffer (of copy_regions()).
    void record_all() {
        std::vector<VkBufferCopy> regions = copy_regions();
        uint32_t region_count = static_cast<uint32_t>(regions.size());
        VkBufferCopy whole{0, 0, bytes_};
        for (CopyCommands* copies : {&compute_copies_, &transfer_copies_}) {
            if (!copies->copy.buffer) continue;  // no transfer-only queue
            record(copies->upload, [&](VkCommandBuffer cb) {
                vkCmdCopyBuffer(cb, upload_staging_.buffer, buffer_a_.buffer, region_count, regions.data());
            });
            record(copies->download, [&](VkCommandBuffer cb) {
                vkCmdCopyBuffer(cb, buffer_a_.buffer, readback_staging_.buffer, region_count, regions.data());
            });
            record(copies->copy, [&](VkCommandBuffer cb) {
                vkCmdCopyBuffer(cb, buffer_a_.buffer, buffer_b_.buffer, region_count, regions.data());
            });
        }
        record(clear_command_, [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, buffer_b_.buffer, 0, VK_WHOLE_SIZE, 0); });
        record(read_destination_command_,
               [&](VkCommandBuffer cb) { vkCmdCopyBuffer(cb, buffer_b_.buffer, readback_staging_.buffer, 1, &whole); });
        if (!kernel_cannot_fit(bytes_).empty()) return;
        VkDescriptorBufferInfo buffers[2] = {{buffer_a_.buffer, 0, VK_WHOLE_SIZE},
                                             {buffer_b_.buffer, 0, VK_WHOLE_SIZE}};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = descriptor_set_;
        write.descriptorCount = 2;
        write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        write.pBufferInfo = buffers;
        vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
        uint32_t count = static_cast<uint32_t>(bytes_ / 16);
        // Same grid rule in every API: one element per thread, at most 65535 groups (then the loop strides).
        uint32_t groups = std::min<uint32_t>({(count + RT_BANDWIDTH_GROUP_SIZE - 1) / RT_BANDWIDTH_GROUP_SIZE, 65535u,
                                              properties_.limits.maxComputeWorkGroupCount[0]});
        record(kernel_command_, [&](VkCommandBuffer cb) {
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
            vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &descriptor_set_, 0,
                                    nullptr);
            vkCmdPushConstants(cb, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof count, &count);
            vkCmdDispatch(cb, groups, 1, 1);
        });
    }

    template <typename Work>
    void record(const Command& command, Work work) {
        check(vkResetCommandBuffer(command.buffer, 0), "vkResetCommandBuffer");
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        check(vkBeginCommandBuffer(command.buffer, &begin), "vkBeginCommandBuffer");
        if (command.timestamps) vkCmdWriteTimestamp(command.buffer, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
        work(command.buffer);
        if (command.timestamps) vkCmdWriteTimestamp(command.buffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
        // After the timed part: make the writes visible to the host and to whatever the next submission does.
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(command.buffer, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                             nullptr, 0, nullptr);
        check(vkEndCommandBuffer(command.buffer), "vkEndCommandBuffer");
    }

    // Submits one recorded command buffer and waits; returns the timestamp difference where there is one.
    std::optional<double> submit(const Command& command) {
        if (command.timestamps) vkResetQueryPool(device_, queries_, 0, 2);
        check(vkResetFences(device_, 1, &fence_), "vkResetFences");
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &command.buffer;
        check(vkQueueSubmit(command.queue, 1, &submit, fence_), "vkQueueSubmit");
        check(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
        if (!command.timestamps) return std::nullopt;
        uint64_t ticks[2] = {};
        check(vkGetQueryPoolResults(device_, queries_, 0, 2, sizeof ticks, ticks, sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              "vkGetQueryPoolResults");
        uint64_t elapsed = (ticks[1] - ticks[0]) & command.timestamp_mask;
        return static_cast<double>(elapsed) * properties_.limits.timestampPeriod * 1e-9;
    }

    static Timed finish(Clock::time_point start, std::optional<double> device_seconds) {
        return Timed{device_seconds, std::chrono::duration<double>(Clock::now() - start).count()};
    }

    void flush(const Buffer& buffer) {
        if (buffer.coherent) return;
        VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, buffer.memory, 0, VK_WHOLE_SIZE};
        check(vkFlushMappedMemoryRanges(device_, 1, &range), "vkFlushMappedMemoryRanges");
    }
    void invalidate(const Buffer& buffer) {
        if (buffer.coherent) return;
        VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, buffer.memory, 0, VK_WHOLE_SIZE};
        check(vkInvalidateMappedMemoryRanges(device_, 1, &range), "vkInvalidateMappedMemoryRanges");
    }

    vk::DeviceCandidate candidate_;  // its compute_family and transfer_family are the queues measured
    VkPhysicalDevice physical_;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceDriverProperties driver_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    VkDeviceSize max_allocation_ = 0;
    std::string pci_address_;
    uint32_t device_local_ = UINT32_MAX, upload_ = UINT32_MAX, readback_ = UINT32_MAX;
    bool has_transfer_ = false;  // a transfer-only queue family exists, and its queue is created
    uint32_t families_[2];       // compute, transfer: the queue families that share every buffer
    bool host_query_reset_ = false;
    bool import_host_ = false;   // PRISM_VULKAN_STAGING=host or host-4k
    bool huge_pages_ = false;    // host: transparent huge pages asked for
    unsigned copy_regions_ = 1;  // PRISM_VULKAN_COPY_REGIONS
    size_t import_alignment_ = kHugePage;
    PFN_vkGetMemoryHostPointerPropertiesEXT host_pointer_properties_ = nullptr;
    std::string huge_page_report_ = "no size measured yet";

    VkDevice device_ = VK_NULL_HANDLE;
    VkCommandPool compute_pool_ = VK_NULL_HANDLE, transfer_pool_ = VK_NULL_HANDLE;
    CopyCommands compute_copies_, transfer_copies_;
    CopyCommands* copies_ = &compute_copies_;  // use_copy_queue()
    Command kernel_command_, clear_command_, read_destination_command_;
    VkQueryPool queries_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkShaderModule shader_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
    VkDescriptorSet descriptor_set_ = VK_NULL_HANDLE;

    size_t bytes_ = 0;
    std::byte* pageable_ = nullptr;
    Buffer buffer_a_, buffer_b_, upload_staging_, readback_staging_;
};

}  // namespace

ApiResult measure_vulkan(const Plan& plan) {
    ApiResult api{"vulkan", "", {}};
    std::unique_ptr<vk::Instance> instance;
    std::vector<vk::DeviceCandidate> devices;
    try {
        instance = std::make_unique<vk::Instance>(false);
        devices = instance->devices();
    } catch (const Error& error) {
        api.unavailable_reason = error.what();
        return api;
    }
    if (devices.empty()) {
        api.unavailable_reason = "no Vulkan device";
        return api;
    }
    for (const vk::DeviceCandidate& device : devices) {
        if (!plan.wants("vulkan", "", device.properties.deviceName)) continue;
        try {
            VulkanDevice copy_device(device, plan.vulkan_staging, plan.vulkan_copy_regions);
            api.devices.push_back(sweep(copy_device, plan));
        } catch (const Error& error) {
            DeviceResult failed{"vulkan", device.properties.deviceName};
            failed.notes.push_back(std::string("device skipped: ") + error.what());
            api.devices.push_back(failed);
        }
    }
    if (api.devices.empty()) api.unavailable_reason = "no Vulkan device matches the --device filters";
    return api;
}

}  // namespace prism::bandwidth
