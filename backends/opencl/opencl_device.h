// OpenCL devices: every device of every platform (in the ICD loader's order), choosing one by index or name, a
// context and profiling queue on it (shared with the viewer's GL where the driver can), and error names. Used by
// the backend (opencl_backend.cpp), the program cache (opencl_program.h), `prism bandwidth` and tests.
#pragma once

#include <CL/cl.h>

#include <string>
#include <vector>

#include "core/render/gl_interop.h"
#include "core/util/non_copyable.h"

namespace prism::opencl {

// "CL_INVALID_VALUE" for -30, ...; "unknown OpenCL error" otherwise.
const char* cl_error_name(cl_int code);
// Without leading and trailing white space (and the NULs OpenCL strings end with).
std::string trim(std::string s);
// A device's text property (CL_DEVICE_NAME, CL_DEVICE_EXTENSIONS, ...), trimmed; "" when the query fails.
std::string device_string(cl_device_id device, cl_device_info what);
// Whether CL_DEVICE_EXTENSIONS lists `extension` (a whole name, not a prefix of another).
bool device_has_extension(cl_device_id device, const std::string& extension);

struct DeviceEntry {
    cl_platform_id platform = nullptr;
    cl_device_id device = nullptr;
    std::string platform_name, platform_vendor, platform_version;
    std::string device_name, device_version, driver_version;
    cl_device_type type = 0;
    cl_uint compute_units = 0;
    cl_ulong global_memory = 0;
    cl_ulong max_alloc = 0;
    cl_device_fp_config fp_config = 0;

    std::string label() const { return platform_name + " [" + device_name + "]"; }
    // What a device filter is matched against.
    std::string haystack() const { return platform_name + " " + platform_vendor + " " + device_name; }
};

// Every device of every platform, in the ICD loader's order. `why_none` says why the list is empty.
std::vector<DeviceEntry> enumerate_devices(std::string& why_none);

// "" = the first GPU of any platform, else the first device; a number = that device of the list; otherwise the
// first device whose platform name/vendor + device name contain the filter (case-insensitive).
DeviceEntry select_device(const std::string& filter);

// Throws prism::Error "opencl: <what> failed on <device>: <error name> (<code>)" unless err is CL_SUCCESS.
void check(cl_int err, const char* what, const DeviceEntry& device);

// A context and an in-order, profiling queue on one device. With `gl`, the context is created together with the
// viewer's GL context where the device can share with it (cl_khr_gl_sharing); otherwise, or when that fails, as
// a plain context, with gl_reason() saying why.
class ClDevice : private NonCopyable {
public:
    explicit ClDevice(const std::string& filter, const GlContextHandles* gl = nullptr);
    ~ClDevice();

    const DeviceEntry& entry() const { return entry_; }
    cl_context context() const { return context_; }
    cl_command_queue queue() const { return queue_; }
    bool shares_gl() const { return gl_reason_.empty(); }  // meaningful only when created with `gl`
    const std::string& gl_reason() const { return gl_reason_; }

private:
    DeviceEntry entry_;
    std::string gl_reason_;  // why the context does not share with GL ("" when it does)
    cl_context context_ = nullptr;
    cl_command_queue queue_ = nullptr;
};

}  // namespace prism::opencl
