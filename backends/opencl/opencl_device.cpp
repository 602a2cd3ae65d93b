#include "backends/opencl/opencl_device.h"

#include <cctype>
#include <optional>

#include "backends/opencl/opencl_gl_interop.h"
#include "core/render/device_filter.h"
#include "core/util/error.h"
#include "core/util/pocl_cache.h"

namespace prism::opencl {
namespace {

// A text property through clGetPlatformInfo or clGetDeviceInfo (the same two-call protocol), trimmed.
template <typename Handle, typename Property>
std::string info_string(cl_int (*query)(Handle, Property, size_t, void*, size_t*), Handle handle, Property what) {
    size_t size = 0;
    if (query(handle, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "";
    std::string s(size, '\0');
    if (query(handle, what, size, s.data(), nullptr) != CL_SUCCESS) return "";
    return trim(s);
}

std::string platform_string(cl_platform_id platform, cl_platform_info what) {
    return info_string(clGetPlatformInfo, platform, what);
}

template <typename T>
T device_value(cl_device_id device, cl_device_info what) {
    T value{};
    clGetDeviceInfo(device, what, sizeof value, &value, nullptr);
    return value;
}

}  // namespace

const char* cl_error_name(cl_int code) {
    switch (code) {
#define PRISM_CL_ERROR(name) \
    case name: return #name;
        PRISM_CL_ERROR(CL_DEVICE_NOT_FOUND)
        PRISM_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
        PRISM_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
        PRISM_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        PRISM_CL_ERROR(CL_OUT_OF_RESOURCES)
        PRISM_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
        PRISM_CL_ERROR(CL_PROFILING_INFO_NOT_AVAILABLE)
        PRISM_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
        PRISM_CL_ERROR(CL_INVALID_VALUE)
        PRISM_CL_ERROR(CL_INVALID_DEVICE)
        PRISM_CL_ERROR(CL_INVALID_CONTEXT)
        PRISM_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
        PRISM_CL_ERROR(CL_INVALID_MEM_OBJECT)
        PRISM_CL_ERROR(CL_INVALID_BINARY)
        PRISM_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
        PRISM_CL_ERROR(CL_INVALID_PROGRAM)
        PRISM_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
        PRISM_CL_ERROR(CL_INVALID_KERNEL_NAME)
        PRISM_CL_ERROR(CL_INVALID_KERNEL)
        PRISM_CL_ERROR(CL_INVALID_ARG_INDEX)
        PRISM_CL_ERROR(CL_INVALID_ARG_VALUE)
        PRISM_CL_ERROR(CL_INVALID_ARG_SIZE)
        PRISM_CL_ERROR(CL_INVALID_KERNEL_ARGS)
        PRISM_CL_ERROR(CL_INVALID_WORK_DIMENSION)
        PRISM_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
        PRISM_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
        PRISM_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
        PRISM_CL_ERROR(CL_INVALID_EVENT)
        PRISM_CL_ERROR(CL_INVALID_OPERATION)
        PRISM_CL_ERROR(CL_INVALID_BUFFER_SIZE)
        PRISM_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
#undef PRISM_CL_ERROR
        case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
        default: return "unknown OpenCL error";
    }
}

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
    size_t first = 0;
    while (first < s.size() && std::isspace(static_cast<unsigned char>(s[first]))) ++first;
    return s.substr(first);
}

std::string device_string(cl_device_id device, cl_device_info what) {
    return info_string(clGetDeviceInfo, device, what);
}

bool device_has_extension(cl_device_id device, const std::string& extension) {
    // The names are separated by spaces: padding both sides matches whole names only. Built by appending, since
    // GCC 12 warns (-Wrestrict) on " " + string.
    std::string listed = " ", wanted = " ";
    listed.append(device_string(device, CL_DEVICE_EXTENSIONS)).append(" ");
    wanted.append(extension).append(" ");
    return listed.find(wanted) != std::string::npos;
}

std::vector<DeviceEntry> enumerate_devices(std::string& why_none) {
    ensure_pocl_cache_dir();  // before PoCL initialises: it needs a usable cache folder
    std::vector<DeviceEntry> devices;
    cl_uint platform_count = 0;
    cl_int err = clGetPlatformIDs(0, nullptr, &platform_count);
    if (err != CL_SUCCESS || platform_count == 0) {
        why_none = "no OpenCL platform (ICD loader found no driver)";
        return devices;
    }
    std::vector<cl_platform_id> platforms(platform_count);
    clGetPlatformIDs(platform_count, platforms.data(), nullptr);
    std::vector<std::string> empty_platforms;
    for (cl_platform_id platform : platforms) {
        cl_uint count = 0;
        if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS || count == 0) {
            empty_platforms.push_back(platform_string(platform, CL_PLATFORM_NAME));
            continue;
        }
        std::vector<cl_device_id> ids(count);
        clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr);
        for (cl_device_id id : ids) {
            DeviceEntry e;
            e.platform = platform;
            e.device = id;
            e.platform_name = platform_string(platform, CL_PLATFORM_NAME);
            e.platform_vendor = platform_string(platform, CL_PLATFORM_VENDOR);
            e.platform_version = platform_string(platform, CL_PLATFORM_VERSION);
            e.device_name = device_string(id, CL_DEVICE_NAME);
            e.device_version = device_string(id, CL_DEVICE_VERSION);
            e.driver_version = device_string(id, CL_DRIVER_VERSION);
            e.type = device_value<cl_device_type>(id, CL_DEVICE_TYPE);
            e.compute_units = device_value<cl_uint>(id, CL_DEVICE_MAX_COMPUTE_UNITS);
            e.global_memory = device_value<cl_ulong>(id, CL_DEVICE_GLOBAL_MEM_SIZE);
            e.max_alloc = device_value<cl_ulong>(id, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
            e.fp_config = device_value<cl_device_fp_config>(id, CL_DEVICE_SINGLE_FP_CONFIG);
            devices.push_back(std::move(e));
        }
    }
    if (devices.empty()) {
        why_none = "no OpenCL device (platforms without devices:";
        for (const std::string& p : empty_platforms) why_none += " " + p;
        why_none += ")";
    }
    return devices;
}

DeviceEntry select_device(const std::string& filter) {
    std::string why;
    std::vector<DeviceEntry> devices = enumerate_devices(why);
    if (devices.empty()) throw Error("opencl: " + why);
    if (filter.empty()) {
        for (const DeviceEntry& d : devices)
            if (d.type & CL_DEVICE_TYPE_GPU) return d;
        return devices.front();
    }
    std::string list;
    for (const DeviceEntry& d : devices) list += (list.empty() ? "" : ", ") + d.label();
    // A number is the device's place in that order (`prism render --backend opencl:all` names devices so).
    if (std::optional<size_t> index = device_index(filter)) {
        if (*index < devices.size()) return devices[*index];
        throw Error("opencl: no device " + filter + " (devices: " + list + ")");
    }
    for (const DeviceEntry& d : devices)
        if (name_matches(d.haystack(), filter)) return d;
    throw Error("opencl: device '" + filter + "' not found (devices: " + list + ")");
}

void check(cl_int err, const char* what, const DeviceEntry& device) {
    if (err != CL_SUCCESS)
        throw Error(std::string("opencl: ") + what + " failed on " + device.device_name + ": " + cl_error_name(err) +
                    " (" + std::to_string(err) + ")");
}

ClDevice::ClDevice(const std::string& filter, const GlContextHandles* gl) : entry_(select_device(filter)) {
    cl_int err = CL_SUCCESS;
    if (gl) {
        opencl_gl::ContextSharing sharing = opencl_gl::context_properties(
            entry_.platform, entry_.device, entry_.platform_name, entry_.device_name, *gl);
        gl_reason_ = sharing.reason;
        if (!sharing.properties.empty()) {
            context_ = clCreateContext(sharing.properties.data(), 1, &entry_.device, nullptr, nullptr, &err);
            if (err != CL_SUCCESS) {
                gl_reason_ = std::string("clCreateContext with the GL context failed: ") + cl_error_name(err);
                context_ = nullptr;
            }
        }
    }
    if (!context_) {
        cl_context_properties props[] = {CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(entry_.platform),
                                         0};
        context_ = clCreateContext(props, 1, &entry_.device, nullptr, nullptr, &err);
        check(err, "clCreateContext", entry_);
    }
    queue_ = clCreateCommandQueue(context_, entry_.device, CL_QUEUE_PROFILING_ENABLE, &err);
    if (err != CL_SUCCESS) {
        clReleaseContext(context_);
        check(err, "clCreateCommandQueue", entry_);
    }
}
ClDevice::~ClDevice() {
    if (queue_) clReleaseCommandQueue(queue_);
    if (context_) clReleaseContext(context_);
}
}  // namespace prism::opencl
