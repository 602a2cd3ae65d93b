// Internals of the OpenCL backend that the tests reach: program building (with the cache) and the layout check.
// Not for other code: the Backend interface is the API.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace prism::opencl_internal {

struct BuildReport {
    std::string device;        // the device it was built for
    std::string options;       // the clBuildProgram options used
    bool from_cache = false;   // the program binary came from the cache
    std::string cache_file;    // where the binary is (or would be) cached; empty when the cache is unusable
    std::string kernel_names;  // the program's __kernel names, ';'-separated (CL_PROGRAM_KERNEL_NAMES)
};

// Builds `source` on the device `device_filter` selects (same rules as "opencl:<filter>") with `options` after the
// fixed ones, through the program cache. Throws prism::Error "opencl: kernel build failed on <device>: <first
// lines of the log>".
BuildReport build_source(const std::string& device_filter, const std::string& source, const std::string& options = "");

// Runs the layout marker kernel (layout.cl, from kernels/layout_table.h): one word per table line, in order
// (sizes for RT_LAYOUT_STRUCT, offsets for RT_LAYOUT_MEMBER).
std::vector<uint32_t> layout_words(const std::string& device_filter);

// The embedded stages program text (for tests that check what is embedded).
const char* stages_source();

// The cache directory in use ($PRISM_CACHE_DIR, else $XDG_CACHE_HOME/prism, else ~/.cache/prism).
std::string cache_directory();

}  // namespace prism::opencl_internal
