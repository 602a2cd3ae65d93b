// OpenCL: every platform's devices. Pageable copies use malloc'd memory; pinned copies use a buffer created with
// CL_MEM_ALLOC_HOST_PTR and mapped once, whose pointer is then handed to clEnqueueRead/WriteBuffer (the fast
// path of NVIDIA's oclBandwidthTest). Device timer: profiling events (COMMAND_START to COMMAND_END).
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <CL/cl_ext.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "backends/opencl/opencl_device.h"
#include "bench/bandwidth/api_runners.h"
#include "bench/bandwidth/copy_device.h"
#include "bench/bandwidth/pci_link.h"
#include "bench/bandwidth/sizes.h"
#include "bench/bandwidth/sweep.h"
#include "core/util/error.h"
#include "kernels/bandwidth_copy.h"

// bandwidth_copy.cl with its includes inlined at build time (cmake/PrismEmbedText.cmake).
extern const char prism_bandwidth_copy_source[];

namespace prism::bandwidth {
namespace {

using Clock = std::chrono::steady_clock;

bool is_out_of_memory(cl_int status) {
    return status == CL_MEM_OBJECT_ALLOCATION_FAILURE || status == CL_OUT_OF_RESOURCES ||
           status == CL_OUT_OF_HOST_MEMORY || status == CL_INVALID_BUFFER_SIZE;
}

// PCI address through cl_khr_pci_bus_info, else NVIDIA's cl_nv_device_attribute_query.
std::string opencl_pci_address(cl_device_id device) {
    std::string extensions = opencl::device_string(device, CL_DEVICE_EXTENSIONS);
    if (extensions.find("cl_khr_pci_bus_info") != std::string::npos) {
        cl_device_pci_bus_info_khr info{};
        if (clGetDeviceInfo(device, CL_DEVICE_PCI_BUS_INFO_KHR, sizeof info, &info, nullptr) == CL_SUCCESS)
            return pci_address(info.pci_domain, info.pci_bus, info.pci_device, info.pci_function);
    }
    if (extensions.find("cl_nv_device_attribute_query") != std::string::npos) {
        const cl_device_info bus_id_nv = 0x4008, slot_id_nv = 0x4009, domain_id_nv = 0x400A;
        cl_uint bus = 0, slot = 0, domain = 0;
        if (clGetDeviceInfo(device, bus_id_nv, sizeof bus, &bus, nullptr) == CL_SUCCESS &&
            clGetDeviceInfo(device, slot_id_nv, sizeof slot, &slot, nullptr) == CL_SUCCESS) {
            clGetDeviceInfo(device, domain_id_nv, sizeof domain, &domain, nullptr);
            return pci_address(domain, bus, slot >> 3, slot & 7);
        }
    }
    return "";
}

// The context and profiling queue are the backend's (backends/opencl/opencl_device.h); the copy kernel is this
// test's own.
class OpenClDevice final : public CopyDevice {
public:
    explicit OpenClDevice(size_t index)
        : cl_(std::to_string(index)),
          entry_(cl_.entry()),
          device_(entry_.device),
          context_(cl_.context()),
          queue_(cl_.queue()) {
        build_kernel();
    }
    ~OpenClDevice() override {
        release();
        if (kernel_) clReleaseKernel(kernel_);
        if (program_) clReleaseProgram(program_);
    }

    DeviceResult describe() const override {
        DeviceResult result;
        result.api = "opencl";
        result.device = entry_.device_name;
        result.platform = entry_.platform_name;
        result.driver = entry_.driver_version;
        result.api_version = entry_.device_version + " (platform " + entry_.platform_version + ")";
        result.pci_address = opencl_pci_address(device_);
        result.device_memory = entry_.global_memory;
        result.details = {"pinned: CL_MEM_ALLOC_HOST_PTR buffer, mapped once, passed to clEnqueueRead/WriteBuffer",
                          "D2D copy: clEnqueueCopyBuffer; timer: profiling events"};
        if (!kernel_error_.empty()) result.notes.push_back("kernel copy unavailable: " + kernel_error_);
        return result;
    }

    std::string cannot_fit(size_t bytes) const override {
        cl_ulong max_alloc = entry_.max_alloc, global = entry_.global_memory;
        if (bytes > max_alloc) return "larger than CL_DEVICE_MAX_MEM_ALLOC_SIZE (" + format_size(max_alloc) + ")";
        if (2 * bytes > global) return "two buffers exceed CL_DEVICE_GLOBAL_MEM_SIZE (" + format_size(global) + ")";
        return "";
    }

    std::string kernel_cannot_fit(size_t) const override {
        return kernel_ ? "" : "the kernel did not build (see the note above)";
    }

    void allocate(size_t bytes, std::byte* pageable) override {
        bytes_ = bytes;
        pageable_ = pageable;
        cl_int status = CL_SUCCESS;
        buffer_a_ = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes, nullptr, &status);
        check_allocation(status, "device buffer A");
        buffer_b_ = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes, nullptr, &status);
        check_allocation(status, "device buffer B");
        pinned_buffer_ = clCreateBuffer(context_, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, bytes, nullptr, &status);
        check_allocation(status, "pinned host buffer");
        pinned_ = static_cast<std::byte*>(clEnqueueMapBuffer(
            queue_, pinned_buffer_, CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, bytes, 0, nullptr, nullptr, &status));
        check_allocation(status, "mapping the pinned host buffer");
        // OpenCL allocates lazily: touch both device buffers now so a size that does not fit fails here.
        cl_uchar zero = 0;
        check_allocation(clEnqueueFillBuffer(queue_, buffer_a_, &zero, 1, 0, bytes, 0, nullptr, nullptr), "buffer A");
        check_allocation(clEnqueueFillBuffer(queue_, buffer_b_, &zero, 1, 0, bytes, 0, nullptr, nullptr), "buffer B");
        check_allocation(clFinish(queue_), "clFinish");
    }

    void release() override {
        if (pinned_) clEnqueueUnmapMemObject(queue_, pinned_buffer_, pinned_, 0, nullptr, nullptr);
        if (queue_) clFinish(queue_);
        for (cl_mem* buffer : {&buffer_a_, &buffer_b_, &pinned_buffer_})
            if (*buffer) clReleaseMemObject(*buffer), *buffer = nullptr;
        pinned_ = nullptr;
    }

    std::byte* pinned_upload() override { return pinned_; }
    std::byte* pinned_download() override { return pinned_; }

    Timed upload(Memory host) override {
        return timed([&](cl_event* event) {
            return clEnqueueWriteBuffer(queue_, buffer_a_, CL_FALSE, 0, bytes_, host_pointer(host), 0, nullptr, event);
        });
    }
    Timed download(Memory host) override {
        return timed([&](cl_event* event) {
            return clEnqueueReadBuffer(queue_, buffer_a_, CL_FALSE, 0, bytes_, host_pointer(host), 0, nullptr, event);
        });
    }
    Timed copy_buffer() override {
        return timed([&](cl_event* event) {
            return clEnqueueCopyBuffer(queue_, buffer_a_, buffer_b_, 0, 0, bytes_, 0, nullptr, event);
        });
    }
    Timed copy_kernel() override {
        cl_uint count = static_cast<cl_uint>(bytes_ / 16);
        check(clSetKernelArg(kernel_, 0, sizeof(cl_mem), &buffer_a_), "clSetKernelArg");
        check(clSetKernelArg(kernel_, 1, sizeof(cl_mem), &buffer_b_), "clSetKernelArg");
        check(clSetKernelArg(kernel_, 2, sizeof count, &count), "clSetKernelArg");
        // Same grid rule in every API: one element per thread, at most 65535 groups (then the loop strides).
        size_t groups = std::min<size_t>((count + group_size_ - 1) / group_size_, 65535);
        size_t global = groups * group_size_;
        return timed([&](cl_event* event) {
            return clEnqueueNDRangeKernel(queue_, kernel_, 1, nullptr, &global, &group_size_, 0, nullptr, event);
        });
    }
    void clear_destination() override {
        cl_uchar zero = 0;
        check(clEnqueueFillBuffer(queue_, buffer_b_, &zero, 1, 0, bytes_, 0, nullptr, nullptr), "clEnqueueFillBuffer");
        check(clFinish(queue_), "clFinish");
    }
    void read_destination() override {
        check(clEnqueueReadBuffer(queue_, buffer_b_, CL_TRUE, 0, bytes_, pageable_, 0, nullptr, nullptr),
              "clEnqueueReadBuffer");
    }

private:
    void check(cl_int status, const char* call) const { opencl::check(status, call, entry_); }
    void check_allocation(cl_int status, const char* what) const {
        if (is_out_of_memory(status))
            throw SizeSkipped(std::string("out of device memory for ") + what + " (" + opencl::cl_error_name(status) +
                              ")");
        check(status, what);
    }
    void* host_pointer(Memory host) const { return host == Memory::Pinned ? static_cast<void*>(pinned_) : pageable_; }

    template <typename Enqueue>
    Timed timed(Enqueue enqueue) {
        cl_event event = nullptr;
        auto start = Clock::now();
        cl_int status = enqueue(&event);
        if (status == CL_SUCCESS) status = clWaitForEvents(1, &event);
        auto end = Clock::now();
        if (event == nullptr || status != CL_SUCCESS) {
            if (event) clReleaseEvent(event);
            check_allocation(status, "the copy");
        }
        cl_ulong begin_ns = 0, end_ns = 0;
        Timed result{std::nullopt, std::chrono::duration<double>(end - start).count()};
        if (clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof begin_ns, &begin_ns, nullptr) ==
                CL_SUCCESS &&
            clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end_ns, &end_ns, nullptr) == CL_SUCCESS &&
            end_ns > begin_ns)
            result.device_seconds = static_cast<double>(end_ns - begin_ns) * 1e-9;
        clReleaseEvent(event);
        return result;
    }

    void build_kernel() {
        const char* source = prism_bandwidth_copy_source;
        cl_int status = CL_SUCCESS;
        program_ = clCreateProgramWithSource(context_, 1, &source, nullptr, &status);
        check(status, "clCreateProgramWithSource");
        status = clBuildProgram(program_, 1, &device_, "-DRT_OPENCL", nullptr, nullptr);
        if (status != CL_SUCCESS) {
            size_t size = 0;
            clGetProgramBuildInfo(program_, device_, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
            std::string log(size, '\0');
            clGetProgramBuildInfo(program_, device_, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
            std::string first_line = log.substr(0, log.find('\n'));
            kernel_error_ = std::string("clBuildProgram failed (") + opencl::cl_error_name(status) + "): " + first_line;
            return;
        }
        kernel_ = clCreateKernel(program_, "bandwidth_copy", &status);
        if (status != CL_SUCCESS) {
            kernel_error_ = std::string("clCreateKernel failed (") + opencl::cl_error_name(status) + ")";
            kernel_ = nullptr;
            return;
        }
        size_t kernel_limit = RT_BANDWIDTH_GROUP_SIZE;
        clGetKernelWorkGroupInfo(kernel_, device_, CL_KERNEL_WORK_GROUP_SIZE, sizeof kernel_limit, &kernel_limit,
                                 nullptr);
        group_size_ = std::min<size_t>(RT_BANDWIDTH_GROUP_SIZE, kernel_limit);
    }

    opencl::ClDevice cl_;
    const opencl::DeviceEntry& entry_;
    cl_device_id device_;
    cl_context context_;
    cl_command_queue queue_;
    cl_program program_ = nullptr;
    cl_kernel kernel_ = nullptr;
    std::string kernel_error_;
    size_t group_size_ = RT_BANDWIDTH_GROUP_SIZE;
    size_t bytes_ = 0;
    std::byte* pageable_ = nullptr;
    std::byte* pinned_ = nullptr;
    cl_mem buffer_a_ = nullptr, buffer_b_ = nullptr, pinned_buffer_ = nullptr;
};

}  // namespace

ApiResult measure_opencl(const Plan& plan) {
    ApiResult api{"opencl", "", {}};
    std::string why_none;
    std::vector<opencl::DeviceEntry> devices = opencl::enumerate_devices(why_none);
    if (devices.empty()) {
        api.unavailable_reason = why_none;
        return api;
    }
    for (size_t i = 0; i < devices.size(); ++i) {
        const opencl::DeviceEntry& entry = devices[i];
        if (!plan.wants("opencl", entry.platform_name, entry.device_name)) continue;
        try {
            OpenClDevice copy_device(i);
            api.devices.push_back(sweep(copy_device, plan));
        } catch (const Error& error) {
            DeviceResult failed{"opencl", entry.device_name, entry.platform_name};
            failed.notes.push_back(std::string("device skipped: ") + error.what());
            api.devices.push_back(failed);
        }
    }
    if (api.devices.empty()) api.unavailable_reason = "no OpenCL device matches the --device filters";
    return api;
}

}  // namespace prism::bandwidth
