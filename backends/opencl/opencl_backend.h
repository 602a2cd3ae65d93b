// The `opencl` backend: OpenCL 1.2 host API (PoCL, NVIDIA OpenCL 3.0, ...). Kernels are the kernels/ stages
// compiled at run time from sources embedded in the binary (stages.cl), with a program-binary cache.
// "opencl" = the first GPU device of any platform, else the first device; "opencl:<filter>" = the first device
// whose platform name/vendor/version + device name/vendor contain <filter> (case-insensitive), GPUs first.
#pragma once

#include "core/render/backend.h"

namespace prism {

BackendFactory opencl_backend_factory();

}  // namespace prism
