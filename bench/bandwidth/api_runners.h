// One entry per API; each is compiled only when its API is enabled at build time (bench/bandwidth/CMakeLists.txt
// defines PRISM_BANDWIDTH_<API>). Each returns its devices' results or why the API could not be measured.
#pragma once

#include "bench/bandwidth/measurement.h"
#include "bench/bandwidth/plan.h"

namespace prism::bandwidth {

ApiResult measure_cuda(const Plan& plan);
ApiResult measure_opencl(const Plan& plan);
ApiResult measure_vulkan(const Plan& plan);

}  // namespace prism::bandwidth
