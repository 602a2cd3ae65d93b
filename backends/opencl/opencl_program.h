// The OpenCL program: built from source with the fixed options of docs/fairness.md, through a binary cache keyed
// by the source, options, platform, device and driver, so a second run skips the compiler.
#pragma once

#include <CL/cl.h>

#include <string>

#include "backends/opencl/opencl_device.h"
#include "backends/opencl/opencl_internal.h"

namespace prism::opencl {

// $PRISM_CACHE_DIR (set but empty: no cache), else $XDG_CACHE_HOME/prism, else ~/.cache/prism; "" for none.
std::string cache_dir();

// Builds `source` for `dev` with the fixed options, then `extra_options` (the backend's own: a stage mask, a register
// budget), then $PRISM_OPENCL_OPTIONS, through the cache at cache_dir()/opencl-<hash>.bin (anything unreadable or
// mismatching is rebuilt from source; a failed write only means no caching). Throws prism::Error "opencl: kernel
// build failed on <device>: <first lines of the log>". `report`, when given, says what happened.
cl_program build_program(const ClDevice& dev, const std::string& source, const std::string& extra_options,
                         opencl_internal::BuildReport* report);

}  // namespace prism::opencl
