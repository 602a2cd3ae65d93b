// The Vulkan backend: memory, launches and timers for the SPIR-V of shaders/ (kernels/ compiled as GLSL).
//
// Commands are recorded into one command buffer on one compute queue: enqueue() records a stage between two
// timestamps — intersect, miss and shade as vkCmdDispatchIndirect, sized on the device from the queue counters
// (kernels/launch_args.h) by generate and shadow, which run on the fixed grid and write every launch's arguments in
// passing (shaders/launch_args.glsl), so a frame has no extra dispatch for it; write() a copy from a host-visible
// staging buffer, zero() a vkCmdFillBuffer. A full memory barrier (compute, transfer and indirect reads) precedes every
// command, which makes the queue behave in order like a CUDA stream or an in-order OpenCL queue. Nothing is submitted
// until read() or finish() (or a full staging buffer or query pool), which submit, wait on a fence and collect the
// timestamps. The host polls that fence (PRISM_VULKAN_WAIT=block: it sleeps in vkWaitForFences instead).
//
// Memory: every device array is its own device-local storage buffer (binding = its line in kernels/data_arrays.h);
// uploads go through a host-visible, coherent, preferably uncached staging buffer; read-backs through a
// host-visible, preferably cached one. Both are at most 64 MiB; larger transfers go in pieces.
//
// Addressing: the stages are built twice (shaders/common.glsl). With descriptors, each array is bound as a storage
// buffer, which can cover at most maxStorageBufferRange (lavapipe: 128 MiB; NVIDIA: 4 GiB). Once any array is
// larger, the backend switches to the variant that reaches every array through its buffer device address (a table
// of addresses at RT_VK_BINDING_ADDRESSES), so a 1080p frame or a large scene also runs on lavapipe.
// PRISM_VULKAN_ADDRESSING=descriptors|addresses forces one variant (tests, benchmarks); PRISM_VULKAN_DISPATCH=fixed
// launches the fixed grid directly instead of indirectly (for measuring what indirect dispatch costs).
#include "backends/vulkan/vulkan_backend.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <map>
#include <optional>
#include <thread>
#include <utility>

#include "backends/vulkan/vulkan_context.h"
#include "backends/vulkan/vulkan_gl_interop.h"
#include "core/render/device_array_book.h"
#include "core/util/environment.h"
#include "core/util/error.h"
#include "shaders/vulkan_bindings.h"
#include "spirv/vulkan_shaders.h"
#include "spirv/vulkan_shaders_address.h"
#include "kernels/launch_args.h"  // as C++ (core defines RT_CPU): slots of the argument buffer

namespace prism {
namespace {

constexpr uint32_t kWorkGroupSize = 128;              // local_size_x of shaders/common.glsl
constexpr VkDeviceSize kTransferChunk = 64ull << 20;  // staging and read-back buffers grow up to this
constexpr uint32_t kQueryCapacity = 2 * 512;          // timestamps per submission (two per dispatch)
static_assert(RT_LAUNCH_SLOTS <= kWorkGroupSize, "shaders/launch_args.comp fills one slot per invocation of one group");
static_assert(RT_VK_BINDING_LAUNCH_ARGS == device_array_count, "data_arrays.h: bindings 0 .. count - 1, in order");

struct StagePush {  // shaders/common.glsl
    uint32_t depth;
    uint32_t groups;
};

std::string mib(uint64_t bytes) {
    char text[32];
    double value = double(bytes) / double(1 << 20);
    if (value == std::floor(value))
        std::snprintf(text, sizeof text, "%.0f MiB", value);
    else
        std::snprintf(text, sizeof text, "%.1f MiB", value);
    return text;
}

VkDeviceSize round_up(VkDeviceSize value, VkDeviceSize multiple) {
    return (value + multiple - 1) / multiple * multiple;
}

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize capacity = 0;  // bytes of the VkBuffer (>= 16, a multiple of 16)
    size_t bytes = 0;           // bytes the user allocated
    void* mapped = nullptr;
    bool coherent = true;
};

struct PendingTiming {
    Stage stage;
    uint32_t depth;
    uint32_t query;  // start; end is query + 1
};

class VulkanBackend final : public Backend, private vk::ImageCopier {
public:
    VulkanBackend(const std::string& filter, const GlContextHandles* gl) : instance_(vk::validation_requested()) {
        try {
            create(filter, gl);
        } catch (...) {
            destroy();
            throw;
        }
    }
    ~VulkanBackend() override { destroy(); }

    BackendInfo info() const override {
        BackendInfo info;
        info.name = "vulkan";
        info.device = physical_.properties.deviceName;
        info.driver = std::string(physical_.driver.driverName) + " " + physical_.driver.driverInfo + "; grid " +
                      std::to_string(grid_.groups) + " x " + std::to_string(kWorkGroupSize) + " (" +
                      std::to_string(grid_.compute_units) + " " + grid_.source + "), " +
                      (indirect_ ? "indirect dispatch" : "fixed dispatch") + ", " +
                      (forced_addressing_ == "addresses" ? "buffer device addresses"
                       : forced_addressing_ == "descriptors" || !address_supported_
                           ? "descriptors"
                           : "descriptors (addresses above maxStorageBufferRange)");
        info.api_version = "Vulkan " + vk::api_version_string(physical_.properties.apiVersion);
        info.device_memory = device_heap_bytes_;
        info.max_buffer = max_buffer_;
        return info;
    }

    void allocate(DeviceArray array, size_t bytes) override {
        Buffer& buffer = arrays_[size_t(array)];
        if (buffer.buffer && buffer.bytes == bytes) return;
        launch_args_fresh_ = false;
        const char* name = device_array_name(array);
        const std::string device = physical_.properties.deviceName;
        if (bytes > physical_.properties.limits.maxStorageBufferRange &&
            (!address_supported_ || forced_addressing_ == "descriptors"))
            throw Error(
                std::string("vulkan: buffer '") + name + "' needs " + mib(bytes) + " but maxStorageBufferRange of " +
                device + " is " + mib(physical_.properties.limits.maxStorageBufferRange) +
                (address_supported_ ? " (PRISM_VULKAN_ADDRESSING=descriptors)" : " and it has no bufferDeviceAddress"));
        if (bytes > max_allocation_)
            throw Error(std::string("vulkan: buffer '") + name + "' needs " + mib(bytes) +
                        " but maxMemoryAllocationSize of " + device + " is " + mib(max_allocation_));
        if (bytes > device_heap_bytes_)
            throw Error(std::string("vulkan: buffer '") + name + "' needs " + mib(bytes) + " but the device heap of " +
                        device + " is " + mib(device_heap_bytes_));
        const size_t device_bytes = round_up(std::max<size_t>(bytes, 16), 16);
        book_->check_fits(array, bytes, device_bytes);
        flush();  // commands already recorded may use the old buffer
        release(buffer);
        book_->forget(array);
        buffer = create_buffer(name, device_bytes, array_usage_, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, false);
        buffer.bytes = bytes;
        book_->record(array, bytes, device_bytes);
        bind(array, buffer);
    }

    // True when the stages run in address mode (see the top of this file).
    bool addressing() const {
        if (forced_addressing_ == "addresses") return true;
        if (forced_addressing_ == "descriptors" || !address_supported_) return false;
        for (const Buffer& b : arrays_)
            if (b.capacity > physical_.properties.limits.maxStorageBufferRange) return true;
        return false;
    }

    void write(DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        book_->check_range(array, bytes, offset);
        if (device_array_role(array) == DeviceArrayRole::Frame) launch_args_fresh_ = false;  // counts may change
        const char* source = static_cast<const char*>(data);
        while (bytes > 0) {
            if (staging_.capacity < kTransferChunk && staging_used_ + bytes > staging_.capacity) {
                flush();
                release(staging_);
                VkDeviceSize capacity =
                    std::min(kTransferChunk, std::max<VkDeviceSize>(round_up(bytes, 1 << 20), 1 << 20));
                staging_ =
                    create_buffer("staging", capacity, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                  VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0,
                                  VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, true);
            }
            if (staging_used_ >= staging_.capacity) {
                flush();
                continue;
            }
            VkDeviceSize piece = std::min<VkDeviceSize>(bytes, staging_.capacity - staging_used_);
            std::memcpy(static_cast<char*>(staging_.mapped) + staging_used_, source, piece);
            begin_command();
            VkBufferCopy region{staging_used_, offset, piece};
            vkCmdCopyBuffer(command_, staging_.buffer, arrays_[size_t(array)].buffer, 1, &region);
            staging_used_ = std::min(staging_.capacity, round_up(staging_used_ + piece, 16));
            source += piece;
            offset += piece;
            bytes -= piece;
        }
    }

    void read(DeviceArray array, void* data, size_t bytes, size_t offset) override {
        book_->check_range(array, bytes, offset);
        char* target = static_cast<char*>(data);
        while (bytes > 0) {
            if (readback_.capacity < std::min<VkDeviceSize>(bytes, kTransferChunk)) {
                flush();
                release(readback_);
                VkDeviceSize capacity =
                    std::min(kTransferChunk, std::max<VkDeviceSize>(round_up(bytes, 1 << 20), 1 << 20));
                readback_ = create_buffer(
                    "readback", capacity, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                    VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0, true);
            }
            VkDeviceSize piece = std::min<VkDeviceSize>(bytes, readback_.capacity);
            copy_to_host_buffer(array, offset, piece, readback_);
            std::memcpy(target, readback_.mapped, piece);
            target += piece;
            offset += piece;
            bytes -= piece;
        }
    }

    // The array straight into host-visible memory kept for it: no copy into the caller's memory after the transfer.
    const void* read_pinned(DeviceArray array, size_t bytes) override {
        book_->check_range(array, bytes, 0);
        Buffer& host = pinned_[size_t(array)];
        if (host.capacity < bytes) {
            flush();
            release(host);
            host = create_buffer("pinned read-back", round_up(std::max<VkDeviceSize>(bytes, 16), 16),
                                 VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                 VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, 0, true);
        }
        if (bytes > 0) copy_to_host_buffer(array, 0, bytes, host);
        return host.mapped;
    }

    void zero(DeviceArray array) override {
        Buffer& buffer = arrays_[size_t(array)];
        if (!buffer.buffer) return;
        if (device_array_role(array) == DeviceArrayRole::Frame) launch_args_fresh_ = false;  // counts may change
        begin_command();
        vkCmdFillBuffer(command_, buffer.buffer, 0, VK_WHOLE_SIZE, 0u);
    }

    void enqueue(Stage stage, uint32_t depth) override {
        if (timestamps_ && queries_used_ + 2 > kQueryCapacity) flush();
        bool address = addressing();
        // The queue-sized stages launch indirectly, sized by the arguments that the GridSizesQueue stages write in
        // passing (kernels/stage_list.h); a launch_args dispatch fills them only where none ran since the counts
        // changed (ray queries).
        const StageLaunch launch = stage_launch(stage);
        bool indirect = indirect_ && (launch == StageLaunch::Queue || launch == StageLaunch::QueueGrows);
        if (indirect && !launch_args_fresh_) {
            begin_command();
            dispatch(pipeline(launch_args_pipelines_, launch_args_address_pipelines_, 0, "launch_args", address), 1, 0);
            launch_args_fresh_ = true;
        }
        begin_command();
        uint32_t query = queries_used_;
        if (timestamps_) vkCmdWriteTimestamp(command_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, query);
        VkPipeline stage_pipeline = pipeline(pipelines_, address_pipelines_, size_t(stage), stage_name(stage), address);
        if (indirect)
            dispatch_indirect(stage_pipeline, VkDeviceSize(rt_launch_slot(RT_LAUNCH_RAYS, depth)) * sizeof(uint4),
                              depth);
        else
            dispatch(stage_pipeline, grid_.groups, depth);
        if (timestamps_) {
            vkCmdWriteTimestamp(command_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, query + 1);
            queries_used_ += 2;
        }
        pending_.push_back(PendingTiming{stage, depth, query});
        if (launch == StageLaunch::GridSizesQueue) launch_args_fresh_ = true;  // it refreshed them
        if (launch == StageLaunch::QueueGrows) launch_args_fresh_ = false;     // it appended rays
    }

    std::vector<StageTiming> finish() override {
        flush();
        return std::exchange(timings_, {});
    }

    GlInteropOffer gl_interop() override { return {gl_.get(), gl_ ? "" : gl_reason_}; }

    // The driver's statistics of each stage's pipeline (the variant frames run now), by the driver's own names; a
    // statistic whose name mentions registers gives StageResources::registers, one that mentions shared memory
    // shared_bytes. NVIDIA's "Local Memory Size" is not read as private bytes: it carries a 2^36 offset.
    KernelResources kernel_resources() const override {
        if (!executable_statistics_)
            return {std::string(physical_.properties.deviceName) + " lacks VK_KHR_pipeline_executable_properties", {}};
        KernelResources resources{"VK_KHR_pipeline_executable_properties", {}};
        const bool address = addressing();
        for (size_t s = 0; s < stage_count; ++s) {
            VkPipeline pipeline = address && address_pipelines_[s] ? address_pipelines_[s] : pipelines_[s];
            if (!pipeline) continue;
            VkPipelineInfoKHR pipeline_info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
            pipeline_info.pipeline = pipeline;
            uint32_t executables = 0;
            vk::check(executable_properties_(device_, &pipeline_info, &executables, nullptr),
                      "vkGetPipelineExecutablePropertiesKHR");
            StageResources stage;
            stage.stage = Stage(s);
            for (uint32_t e = 0; e < executables; ++e) {
                VkPipelineExecutableInfoKHR executable{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
                executable.pipeline = pipeline;
                executable.executableIndex = e;
                uint32_t count = 0;
                vk::check(executable_statistics_(device_, &executable, &count, nullptr),
                          "vkGetPipelineExecutableStatisticsKHR");
                std::vector<VkPipelineExecutableStatisticKHR> statistics(
                    count, VkPipelineExecutableStatisticKHR{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
                vk::check(executable_statistics_(device_, &executable, &count, statistics.data()),
                          "vkGetPipelineExecutableStatisticsKHR");
                for (const VkPipelineExecutableStatisticKHR& statistic : statistics) {
                    std::string value = statistic_text(statistic);
                    stage.statistics.emplace_back(statistic.name, value);
                    std::string name = statistic.name;
                    std::transform(name.begin(), name.end(), name.begin(),
                                   [](unsigned char c) { return char(std::tolower(c)); });
                    if (statistic.format != VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR) continue;
                    if (name.find("register") != std::string::npos) stage.registers = int(statistic.value.u64);
                    if (name.find("shared") != std::string::npos)
                        stage.shared_bytes = static_cast<long long>(statistic.value.u64);
                }
            }
            resources.stages.push_back(stage);
        }
        return resources;
    }

    static std::string statistic_text(const VkPipelineExecutableStatisticKHR& statistic) {
        switch (statistic.format) {
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: return statistic.value.b32 ? "true" : "false";
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: return std::to_string(statistic.value.i64);
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: return std::to_string(statistic.value.u64);
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR: return std::to_string(statistic.value.f64);
            default: return "?";
        }
    }

    void dispatch_module(std::span<const uint32_t> spirv, uint32_t groups, uint32_t push) {
        auto found = extra_pipelines_.find(spirv.data());
        if (found == extra_pipelines_.end())
            found = extra_pipelines_.emplace(spirv.data(), create_pipeline(spirv, "module")).first;
        begin_command();
        dispatch(found->second, groups, push);
        launch_args_fresh_ = false;  // a module may write anything, the counters included
    }

    // For the tests: the variant the next stage would run with, and whether launches are indirect.
    bool uses_addresses() const { return addressing(); }
    bool uses_indirect_dispatch() const { return indirect_; }
    bool polls_fence() const { return poll_fence_; }

private:
    // vk::ImageCopier, for the Vulkan-GL path: the image array into the exported buffer, handed to and taken back
    // from GL by queue family ownership transfers (VK_QUEUE_FAMILY_EXTERNAL), as the spec asks for memory another
    // API uses. It goes into the frame's own vkQueueSubmit and fence, but in a second batch with a command buffer of
    // its own: the shared semaphores' wait (GL has read the buffer) then holds back only the copy, never the
    // frame's stages — the GPU renders the next frame while it still switches to GL for the last one's draw.
    void copy_image_to(VkBuffer target, VkDeviceSize bytes, bool acquire, VkSemaphore wait,
                       VkSemaphore signal) override {
        if (!copy_command_) {
            VkCommandBufferAllocateInfo command_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
            command_info.commandPool = command_pool_;
            command_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
            command_info.commandBufferCount = 1;
            vk::check(vkAllocateCommandBuffers(device_, &command_info, &copy_command_), "vkAllocateCommandBuffers");
        }
        begin_command();  // the frame's batch goes with it, even if nothing else is recorded after the copy
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vk::check(vkBeginCommandBuffer(copy_command_, &begin), "vkBeginCommandBuffer (copy)");
        // A barrier's first scope reaches back over earlier batches in submission order: the frame's writes of
        // `image` (resolve) happen before the copy reads it.
        VkMemoryBarrier after_frame{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        after_frame.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        after_frame.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(copy_command_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                             &after_frame, 0, nullptr, 0, nullptr);
        record_image_copy(copy_command_, target, bytes, acquire);
        vk::check(vkEndCommandBuffer(copy_command_), "vkEndCommandBuffer (copy)");
        copy_recorded_ = true;
        copy_wait_ = wait;
        copy_signal_ = signal;
    }

    // The copy itself, with the queue family ownership transfers around it.
    void record_image_copy(VkCommandBuffer command, VkBuffer target, VkDeviceSize bytes, bool acquire) {
        VkBufferMemoryBarrier ownership{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
        ownership.buffer = target;
        ownership.size = VK_WHOLE_SIZE;
        if (acquire) {
            ownership.srcQueueFamilyIndex = VK_QUEUE_FAMILY_EXTERNAL;
            ownership.dstQueueFamilyIndex = physical_.compute_family;
            ownership.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            vkCmdPipelineBarrier(command, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                                 nullptr, 1, &ownership, 0, nullptr);
        }
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(command, arrays_[size_t(DeviceArray::image)].buffer, target, 1, &region);
        ownership.srcQueueFamilyIndex = physical_.compute_family;
        ownership.dstQueueFamilyIndex = VK_QUEUE_FAMILY_EXTERNAL;
        ownership.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        ownership.dstAccessMask = 0;
        vkCmdPipelineBarrier(command, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0,
                             nullptr, 1, &ownership, 0, nullptr);
    }

    void create(const std::string& filter, const GlContextHandles* gl) {
        physical_ = instance_.select(filter);
        grid_ = vk::choose_grid(physical_);
        vkGetPhysicalDeviceMemoryProperties(physical_.handle, &memory_);
        VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
        VkPhysicalDeviceProperties2 properties2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        properties2.pNext = &maintenance3;
        vkGetPhysicalDeviceProperties2(physical_.handle, &properties2);
        max_allocation_ = maintenance3.maxMemoryAllocationSize;
        for (uint32_t h = 0; h < memory_.memoryHeapCount; ++h)
            if (memory_.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
                device_heap_bytes_ = std::max<size_t>(device_heap_bytes_, memory_.memoryHeaps[h].size);
        book_.emplace("vulkan", physical_.properties.deviceName, device_heap_bytes_);

        // Buffer device addresses (and the 64-bit integers that hold them) let arrays exceed maxStorageBufferRange.
        VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        features.pNext = &features12;
        vkGetPhysicalDeviceFeatures2(physical_.handle, &features);
        address_supported_ = features12.bufferDeviceAddress && features.features.shaderInt64;
        forced_addressing_ = setting_choice(Setting::VulkanAddressing, {"auto", "descriptors", "addresses"}, "vulkan");
        if (forced_addressing_ == "auto") forced_addressing_.clear();
        if (forced_addressing_ == "addresses" && !address_supported_)
            throw Error(std::string("vulkan: PRISM_VULKAN_ADDRESSING=addresses but ") +
                        physical_.properties.deviceName + " lacks bufferDeviceAddress or shaderInt64");
        indirect_ = setting_choice(Setting::VulkanDispatch, {"indirect", "fixed"}, "vulkan") != "fixed";
        // On a CPU device (lavapipe) a polling host thread would take a core from the threads that run the stages.
        poll_fence_ = setting_choice(Setting::VulkanWait, {"poll", "block"}, "vulkan") != "block" &&
                      physical_.properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
        max_buffer_ = std::min<size_t>(max_allocation_, device_heap_bytes_);
        if (!address_supported_ || forced_addressing_ == "descriptors")
            max_buffer_ = std::min<size_t>(max_buffer_, physical_.properties.limits.maxStorageBufferRange);
        array_usage_ = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                       VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                       (address_supported_ ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT : 0);

        std::vector<VkDeviceQueueCreateInfo> queues = vk::queue_create_infos(physical_, false);
        VkPhysicalDeviceVulkan12Features enable12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        enable12.bufferDeviceAddress = address_supported_;
        VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        enable.features.shaderInt64 = address_supported_;
        enable.pNext = &enable12;
        // Vulkan-GL needs its extensions enabled at device creation; without them the backend runs as before.
        vk::GlSharingPlan gl_plan;
        if (gl) gl_plan = vk::plan_gl_sharing(physical_, *gl);
        gl_reason_ = gl ? gl_plan.reason : "GL interop was not requested";
        std::vector<const char*> extensions;
        if (gl && gl_plan.reason.empty()) extensions = gl_plan.extensions;
        // The compiled stages' statistics (registers, spills) where the driver reports them: kernel_resources().
        VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable_info{
            VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
        if (vk::has_device_extension(physical_.handle, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME)) {
            VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
            query.pNext = &executable_info;
            vkGetPhysicalDeviceFeatures2(physical_.handle, &query);
            executable_info.pNext = nullptr;
        }
        if (executable_info.pipelineExecutableInfo) {
            extensions.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
            enable12.pNext = &executable_info;
        }
        VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        device_info.pNext = &enable;
        device_info.queueCreateInfoCount = uint32_t(queues.size());
        device_info.pQueueCreateInfos = queues.data();
        device_info.enabledExtensionCount = uint32_t(extensions.size());
        device_info.ppEnabledExtensionNames = extensions.data();
        vk::check(vkCreateDevice(physical_.handle, &device_info, nullptr, &device_), "vkCreateDevice");
        if (executable_info.pipelineExecutableInfo) {
            executable_properties_ = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
                vkGetDeviceProcAddr(device_, "vkGetPipelineExecutablePropertiesKHR"));
            executable_statistics_ = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
                vkGetDeviceProcAddr(device_, "vkGetPipelineExecutableStatisticsKHR"));
        }
        queue_ = vk::get_device_queues(device_, physical_, false).compute;

        VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pool_info.queueFamilyIndex = physical_.compute_family;
        vk::check(vkCreateCommandPool(device_, &pool_info, nullptr, &command_pool_), "vkCreateCommandPool");
        VkCommandBufferAllocateInfo command_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        command_info.commandPool = command_pool_;
        command_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        command_info.commandBufferCount = 1;
        vk::check(vkAllocateCommandBuffers(device_, &command_info, &command_), "vkAllocateCommandBuffers");
        VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        vk::check(vkCreateFence(device_, &fence_info, nullptr, &fence_), "vkCreateFence");

        uint32_t family_count = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical_.handle, &family_count, nullptr);
        std::vector<VkQueueFamilyProperties> families(family_count);
        vkGetPhysicalDeviceQueueFamilyProperties(physical_.handle, &family_count, families.data());
        timestamp_bits_ = families[physical_.compute_family].timestampValidBits;
        timestamps_ = timestamp_bits_ > 0;
        if (timestamps_) {
            VkQueryPoolCreateInfo query_info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
            query_info.queryCount = kQueryCapacity;
            vk::check(vkCreateQueryPool(device_, &query_info, nullptr, &query_pool_), "vkCreateQueryPool");
        }

        // The descriptor set layout is kernels/data_arrays.h: binding = first column, all storage buffers.
        std::vector<VkDescriptorSetLayoutBinding> bindings;
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    bindings.push_back({slot, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
        bindings.push_back(
            {RT_VK_BINDING_LAUNCH_ARGS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
        bindings.push_back(
            {RT_VK_BINDING_ADDRESSES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
        VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        set_info.bindingCount = uint32_t(bindings.size());
        set_info.pBindings = bindings.data();
        vk::check(vkCreateDescriptorSetLayout(device_, &set_info, nullptr, &set_layout_),
                  "vkCreateDescriptorSetLayout");
        VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, uint32_t(bindings.size())};
        VkDescriptorPoolCreateInfo descriptor_pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        descriptor_pool_info.maxSets = 1;
        descriptor_pool_info.poolSizeCount = 1;
        descriptor_pool_info.pPoolSizes = &pool_size;
        vk::check(vkCreateDescriptorPool(device_, &descriptor_pool_info, nullptr, &descriptor_pool_),
                  "vkCreateDescriptorPool");
        VkDescriptorSetAllocateInfo set_alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        set_alloc.descriptorPool = descriptor_pool_;
        set_alloc.descriptorSetCount = 1;
        set_alloc.pSetLayouts = &set_layout_;
        vk::check(vkAllocateDescriptorSets(device_, &set_alloc, &descriptor_set_), "vkAllocateDescriptorSets");

        VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(StagePush)};
        VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layout_info.setLayoutCount = 1;
        layout_info.pSetLayouts = &set_layout_;
        layout_info.pushConstantRangeCount = 1;
        layout_info.pPushConstantRanges = &push;
        vk::check(vkCreatePipelineLayout(device_, &layout_info, nullptr, &pipeline_layout_), "vkCreatePipelineLayout");
        // Descriptor-mode pipelines now (the common case); address-mode ones when first needed.
        for (size_t s = 0; s < stage_count; ++s)
            pipeline(pipelines_, address_pipelines_, s, stage_name(Stage(s)), false);
        if (indirect_) pipeline(launch_args_pipelines_, launch_args_address_pipelines_, 0, "launch_args", false);

        // Until an array is allocated its binding points at a small placeholder, so every set is valid.
        placeholder_ = create_buffer("placeholder", 16, array_usage_, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, 0, false);
        for (size_t a = 0; a < device_array_count; ++a) bind(DeviceArray(a), placeholder_);
        launch_args_ = create_buffer("launch_args", RT_LAUNCH_SLOTS * sizeof(uint4), array_usage_,
                                     VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, 0, false);
        bind_extra(RT_VK_BINDING_LAUNCH_ARGS, launch_args_);
        addresses_ = create_buffer("addresses", device_array_count * sizeof(uint64_t), array_usage_,
                                   VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, 0, false);
        bind_extra(RT_VK_BINDING_ADDRESSES, addresses_);
        if (gl && gl_plan.reason.empty()) gl_ = vk::create_gl_interop(device_, physical_, memory_, *this, gl_plan);
    }

    // The pipeline of one entry point in the variant asked for, created on first use.
    VkPipeline pipeline(std::array<VkPipeline, stage_count>& descriptor_set,
                        std::array<VkPipeline, stage_count>& address, size_t index, const char* name,
                        bool use_addresses) {
        VkPipeline& slot = use_addresses ? address[index] : descriptor_set[index];
        if (slot) return slot;
        std::span<const uint32_t> spirv =
            use_addresses ? spirv::vulkan_shaders_address(name) : spirv::vulkan_shaders(name);
        if (spirv.empty()) throw Error(std::string("vulkan: no embedded SPIR-V for '") + name + "'");
        slot = create_pipeline(spirv, name);
        return slot;
    }

    void destroy() {
        if (!device_) return;
        gl_.reset();  // its buffer and semaphores belong to this device
        vkDeviceWaitIdle(device_);
        for (Buffer& b : arrays_) release(b);
        release(placeholder_);
        release(launch_args_);
        release(addresses_);
        release(staging_);
        release(readback_);
        for (Buffer& b : pinned_) release(b);
        for (auto* set : {&pipelines_, &address_pipelines_, &launch_args_pipelines_, &launch_args_address_pipelines_})
            for (VkPipeline p : *set)
                if (p) vkDestroyPipeline(device_, p, nullptr);
        for (auto& [key, p] : extra_pipelines_) vkDestroyPipeline(device_, p, nullptr);
        if (pipeline_layout_) vkDestroyPipelineLayout(device_, pipeline_layout_, nullptr);
        if (descriptor_pool_) vkDestroyDescriptorPool(device_, descriptor_pool_, nullptr);
        if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
        if (query_pool_) vkDestroyQueryPool(device_, query_pool_, nullptr);
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
        vkDestroyDevice(device_, nullptr);
        device_ = VK_NULL_HANDLE;
    }

    VkPipeline create_pipeline(std::span<const uint32_t> spirv, const char* name) {
        VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        module_info.codeSize = spirv.size_bytes();
        module_info.pCode = spirv.data();
        VkShaderModule module = VK_NULL_HANDLE;
        vk::check(vkCreateShaderModule(device_, &module_info, nullptr, &module), "vkCreateShaderModule");
        VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipeline_info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipeline_info.stage.module = module;
        pipeline_info.stage.pName = "main";
        // Specialization constant 0, rt_vk_take_work (shaders/common.glsl): the grid loop on a CPU device.
        const VkBool32 take_work = physical_.properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
        const VkSpecializationMapEntry take_work_entry{0, 0, sizeof take_work};
        const VkSpecializationInfo specialization{1, &take_work_entry, sizeof take_work, &take_work};
        pipeline_info.stage.pSpecializationInfo = &specialization;
        pipeline_info.layout = pipeline_layout_;
        if (executable_statistics_) pipeline_info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
        VkPipeline pipeline = VK_NULL_HANDLE;
        VkResult result = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline);
        vkDestroyShaderModule(device_, module, nullptr);
        if (result != VK_SUCCESS)
            throw Error(std::string("vulkan: creating the pipeline of '") + name + "' on " +
                        physical_.properties.deviceName + " failed: " + vk::result_name(result));
        return pipeline;
    }

    Buffer create_buffer(const char* name, VkDeviceSize capacity, VkBufferUsageFlags usage,
                         VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred, VkMemoryPropertyFlags avoided,
                         bool map) {
        Buffer b;
        b.capacity = capacity;
        VkBufferCreateInfo buffer_info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        buffer_info.size = capacity;
        buffer_info.usage = usage;
        buffer_info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        vk::check(vkCreateBuffer(device_, &buffer_info, nullptr, &b.buffer), "vkCreateBuffer");
        VkMemoryRequirements requirements;
        vkGetBufferMemoryRequirements(device_, b.buffer, &requirements);
        uint32_t type = vk::find_memory_type(memory_, requirements.memoryTypeBits, required, preferred, avoided);
        if (type == UINT32_MAX) {
            vkDestroyBuffer(device_, b.buffer, nullptr);
            throw Error(std::string("vulkan: no suitable memory type for buffer '") + name + "' on " +
                        physical_.properties.deviceName);
        }
        VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
        flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) alloc.pNext = &flags;
        alloc.allocationSize = requirements.size;
        alloc.memoryTypeIndex = type;
        VkResult result = vkAllocateMemory(device_, &alloc, nullptr, &b.memory);
        if (result != VK_SUCCESS) {
            vkDestroyBuffer(device_, b.buffer, nullptr);
            throw Error(std::string("vulkan: buffer '") + name + "' (" + mib(capacity) +
                        ") does not fit in the memory of " + physical_.properties.deviceName + ": " +
                        vk::result_name(result));
        }
        vk::check(vkBindBufferMemory(device_, b.buffer, b.memory, 0), "vkBindBufferMemory");
        b.coherent = memory_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        if (map) vk::check(vkMapMemory(device_, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
        return b;
    }

    // Copies [offset, offset + bytes) of the array to the start of host-visible `host` and waits for it.
    void copy_to_host_buffer(DeviceArray array, VkDeviceSize offset, VkDeviceSize bytes, const Buffer& host) {
        begin_command();
        VkBufferCopy region{offset, 0, bytes};
        vkCmdCopyBuffer(command_, arrays_[size_t(array)].buffer, host.buffer, 1, &region);
        VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(command_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0,
                             nullptr, 0, nullptr);
        flush();
        if (!host.coherent) {
            VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
            range.memory = host.memory;
            range.size = VK_WHOLE_SIZE;
            vk::check(vkInvalidateMappedMemoryRanges(device_, 1, &range), "vkInvalidateMappedMemoryRanges");
        }
    }

    void release(Buffer& b) {
        if (b.buffer) vkDestroyBuffer(device_, b.buffer, nullptr);
        if (b.memory) vkFreeMemory(device_, b.memory, nullptr);  // unmaps too
        b = Buffer{};
    }

    // Points the array's descriptor (its first maxStorageBufferRange bytes: a larger array is only reached in
    // address mode) and its entry in the address table at `buffer`.
    void bind(DeviceArray array, const Buffer& buffer) {
        bind_extra(uint32_t(array), buffer);
        if (address_supported_) {
            VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
            info.buffer = buffer.buffer;
            address_table_[size_t(array)] = vkGetBufferDeviceAddress(device_, &info);
            addresses_dirty_ = true;
        }
    }

    void bind_extra(uint32_t binding, const Buffer& buffer) {
        VkDescriptorBufferInfo info{
            buffer.buffer, 0,
            std::min<VkDeviceSize>(buffer.capacity, physical_.properties.limits.maxStorageBufferRange)};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = descriptor_set_;
        write.dstBinding = binding;
        write.descriptorCount = 1;
        write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        write.pBufferInfo = &info;
        vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
    }

    // Starts recording if needed, then orders the next command after every earlier one (compute, transfer and
    // the indirect-argument reads of vkCmdDispatchIndirect).
    void begin_command() {
        if (!recording_) {
            VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
            begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
            vk::check(vkBeginCommandBuffer(command_, &begin), "vkBeginCommandBuffer");
            recording_ = true;
            if (timestamps_) vkCmdResetQueryPool(command_, query_pool_, 0, kQueryCapacity);  // once per submission
        }
        if (addresses_dirty_) {  // the address table follows every (re)allocation, in stream order
            addresses_dirty_ = false;
            full_barrier();
            vkCmdUpdateBuffer(command_, addresses_.buffer, 0, sizeof address_table_, address_table_.data());
        }
        full_barrier();
    }

    void full_barrier() {
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                                VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
        VkPipelineStageFlags source = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkPipelineStageFlags target = source | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT;
        vkCmdPipelineBarrier(command_, source, target, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    }

    void bind_for_dispatch(VkPipeline pipeline, uint32_t depth) {
        StagePush push{depth, grid_.groups};
        vkCmdBindPipeline(command_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdBindDescriptorSets(command_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &descriptor_set_, 0,
                                nullptr);
        vkCmdPushConstants(command_, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
    }

    void dispatch(VkPipeline pipeline, uint32_t groups, uint32_t depth) {
        bind_for_dispatch(pipeline, depth);
        vkCmdDispatch(command_, groups, 1, 1);
    }

    void dispatch_indirect(VkPipeline pipeline, VkDeviceSize offset, uint32_t depth) {
        bind_for_dispatch(pipeline, depth);
        vkCmdDispatchIndirect(command_, launch_args_.buffer, offset);
    }

    // Submits what was recorded (and the Vulkan-GL copy, when one is pending, as a second batch of the same
    // vkQueueSubmit: it alone waits on / signals the semaphores shared with GL), waits on the one fence, and turns
    // the timestamps into stage timings.
    void flush() {
        if (!recording_) return;
        recording_ = false;
        vk::check(vkEndCommandBuffer(command_), "vkEndCommandBuffer");
        std::array<VkSubmitInfo, 2> batches{};
        batches[0] = VkSubmitInfo{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        batches[0].commandBufferCount = 1;
        batches[0].pCommandBuffers = &command_;
        VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        if (copy_recorded_) {
            batches[1] = VkSubmitInfo{VK_STRUCTURE_TYPE_SUBMIT_INFO};
            batches[1].commandBufferCount = 1;
            batches[1].pCommandBuffers = &copy_command_;
            if (copy_wait_) {
                batches[1].waitSemaphoreCount = 1;
                batches[1].pWaitSemaphores = &copy_wait_;
                batches[1].pWaitDstStageMask = &wait_stage;
            }
            if (copy_signal_) {
                batches[1].signalSemaphoreCount = 1;
                batches[1].pSignalSemaphores = &copy_signal_;
            }
        }
        vk::check(vkQueueSubmit(queue_, copy_recorded_ ? 2 : 1, batches.data(), fence_), "vkQueueSubmit");
        copy_recorded_ = false;
        copy_wait_ = copy_signal_ = VK_NULL_HANDLE;
        VkResult waited = wait_for_fence();
        if (waited == VK_ERROR_DEVICE_LOST)
            throw Error(std::string("vulkan: device lost on ") + physical_.properties.deviceName +
                        " (a stage crashed or ran past the driver's time limit)");
        vk::check(waited, "vkWaitForFences");
        vk::check(vkResetFences(device_, 1, &fence_), "vkResetFences");
        vk::check(vkResetCommandBuffer(command_, 0), "vkResetCommandBuffer");
        staging_used_ = 0;

        std::vector<uint64_t> stamps(queries_used_);
        if (queries_used_ > 0)
            vk::check(vkGetQueryPoolResults(device_, query_pool_, 0, queries_used_, stamps.size() * sizeof(uint64_t),
                                            stamps.data(), sizeof(uint64_t),
                                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
                      "vkGetQueryPoolResults");
        uint64_t mask = timestamp_bits_ >= 64 ? ~0ull : (1ull << timestamp_bits_) - 1;
        for (const PendingTiming& p : pending_) {
            double ms = 0.0;
            if (timestamps_) {
                uint64_t ticks = (stamps[p.query + 1] - stamps[p.query]) & mask;
                ms = double(ticks) * double(physical_.properties.limits.timestampPeriod) * 1e-6;
            }
            timings_.push_back(StageTiming{p.stage, p.depth, ms});
        }
        pending_.clear();
        queries_used_ = 0;
    }

    // CUDA's wait for a stream spins by default where the host has more cores than GPUs; vkWaitForFences sleeps on
    // NVIDIA's driver, and waking it cost a frame of the seed's setting 0.1-0.4 ms (docs/vulkan.md). So the host
    // polls the fence, yielding its core to any thread that wants it.
    VkResult wait_for_fence() {
        if (poll_fence_) {
            for (;;) {
                VkResult status = vkGetFenceStatus(device_, fence_);
                if (status != VK_NOT_READY) return status;
                std::this_thread::yield();
            }
        }
        return vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX);
    }

    vk::Instance instance_;
    vk::DeviceCandidate physical_;
    vk::GridChoice grid_;
    VkPhysicalDeviceMemoryProperties memory_{};
    size_t max_allocation_ = 0;
    size_t device_heap_bytes_ = 0;
    size_t max_buffer_ = 0;
    std::optional<DeviceArrayBook> book_;  // made once the device heap is known

    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkCommandPool command_pool_ = VK_NULL_HANDLE;
    VkCommandBuffer command_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    bool poll_fence_ = true;  // PRISM_VULKAN_WAIT != block, and not a CPU device
    // The frame's Vulkan-GL copy, submitted with the next flush as a batch of its own, and the semaphores shared
    // with GL that batch waits on and signals (or none).
    VkCommandBuffer copy_command_ = VK_NULL_HANDLE;
    bool copy_recorded_ = false;
    VkSemaphore copy_wait_ = VK_NULL_HANDLE, copy_signal_ = VK_NULL_HANDLE;
    bool recording_ = false;

    VkQueryPool query_pool_ = VK_NULL_HANDLE;
    bool timestamps_ = false;
    uint32_t timestamp_bits_ = 0;
    uint32_t queries_used_ = 0;
    std::vector<PendingTiming> pending_;
    std::vector<StageTiming> timings_;

    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
    VkDescriptorSet descriptor_set_ = VK_NULL_HANDLE;
    VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
    std::array<VkPipeline, stage_count> pipelines_{};          // descriptor mode
    std::array<VkPipeline, stage_count> address_pipelines_{};  // address mode
    // VK_KHR_pipeline_executable_properties, where the device has it (null otherwise).
    PFN_vkGetPipelineExecutablePropertiesKHR executable_properties_ = nullptr;
    PFN_vkGetPipelineExecutableStatisticsKHR executable_statistics_ = nullptr;
    std::array<VkPipeline, stage_count> launch_args_pipelines_{};          // [0] only
    std::array<VkPipeline, stage_count> launch_args_address_pipelines_{};  // [0] only
    bool address_supported_ = false;
    std::string forced_addressing_;  // PRISM_VULKAN_ADDRESSING: "", "descriptors" or "addresses"
    bool indirect_ = true;           // PRISM_VULKAN_DISPATCH != fixed
    VkBufferUsageFlags array_usage_ = 0;
    std::map<const uint32_t*, VkPipeline> extra_pipelines_;

    std::array<Buffer, device_array_count> arrays_{};
    Buffer placeholder_;
    Buffer launch_args_;  // RT_LAUNCH_SLOTS x uint4: vkCmdDispatchIndirect arguments
    Buffer addresses_;    // device_array_count x uint64: the address table of address mode
    std::array<uint64_t, device_array_count> address_table_{};
    bool addresses_dirty_ = false;
    // Whether launch_args_ holds the counts of the counters as they are (cleared by anything that changes them:
    // host writes to counters or frame, a reallocation, a shade stage).
    bool launch_args_fresh_ = false;
    Buffer staging_;
    VkDeviceSize staging_used_ = 0;
    Buffer readback_;
    std::array<Buffer, device_array_count> pinned_{};  // read_pinned's host memory, by slot

    std::unique_ptr<GlInterop> gl_;  // Vulkan-GL, when the viewer asked and GL can import this device's memory
    std::string gl_reason_;          // why gl_ is null
};

}  // namespace

std::span<const uint32_t> vulkan_embedded_spirv(std::string_view name) { return spirv::vulkan_shaders(name); }

void vulkan_dispatch_module(Backend& backend, std::span<const uint32_t> spirv, uint32_t groups, uint32_t push) {
    auto* vulkan = dynamic_cast<VulkanBackend*>(&backend);
    if (!vulkan) throw Error("vulkan_dispatch_module: not a Vulkan backend");
    vulkan->dispatch_module(spirv, groups, push);
}

VulkanLaunchMode vulkan_launch_mode(const Backend& backend) {
    auto* vulkan = dynamic_cast<const VulkanBackend*>(&backend);
    if (!vulkan) throw Error("vulkan_launch_mode: not a Vulkan backend");
    return VulkanLaunchMode{vulkan->uses_addresses(), vulkan->uses_indirect_dispatch(), vulkan->polls_fence()};
}

BackendFactory vulkan_backend_factory() {
    BackendFactory factory;
    factory.name = "vulkan";
    factory.create = [](const std::string& filter, const GlContextHandles* gl) -> std::unique_ptr<Backend> {
        return std::make_unique<VulkanBackend>(filter, gl);
    };
    factory.probe = [] {
        BackendAvailability a;
        a.name = "vulkan";
        try {
            vk::Instance instance(false);
            for (const vk::DeviceCandidate& d : instance.devices()) {
                a.devices.push_back(d.describe());
                if (d.unusable.empty()) a.available = true;
            }
            if (a.devices.empty())
                a.detail = "Vulkan: no compute-capable device (no physical device found)";
            else if (!a.available)
                a.detail = "Vulkan: no compute-capable device (none usable)";
            else
                a.detail = "kernels/ compiled to SPIR-V (GLSL 4.60, Vulkan 1.2) as compute pipelines";
        } catch (const Error& e) {
            a.available = false;
            a.detail = e.what();
        }
        return a;
    };
    return factory;
}

}  // namespace prism
