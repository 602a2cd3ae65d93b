// Runs the plan on one device through the CopyDevice interface: the same order, warm-up, repeats and data checks
// for every API.
#pragma once

#include "bench/bandwidth/copy_device.h"
#include "bench/bandwidth/plan.h"

namespace prism::bandwidth {

DeviceResult sweep(CopyDevice& device, const Plan& plan);

}  // namespace prism::bandwidth
