// The `cuda` backend: kernels/ compiled by nvcc (stages.cu), plain cudaMalloc buffers, one stream, CUDA events
// around every launch. "cuda" is device 0; "cuda:<index>" or "cuda:<name substring>" picks another.
#pragma once

#include "core/device_memory_limit.h"
#include "core/launch_config.h"
#include <cstddef>
#include <optional>
#include <string>

#include "core/backend.h"

namespace prism {

BackendFactory cuda_backend_factory();

namespace cuda {
// Launch configuration shared by every stage (docs/fairness.md; the OpenCL backend uses the same rule):
// a fixed grid of kBlocksPerMultiprocessor x SM count blocks of kThreadsPerBlock, grid-stride loops.
inline constexpr unsigned kThreadsPerBlock = 128;
inline constexpr unsigned kBlocksPerMultiprocessor = prism::kWorkGroupsPerComputeUnit;

// PRISM_DEVICE_MEMORY_LIMIT: the most bytes the backend may allocate in all (to exercise the out-of-memory
// path without a full device). Unset: no limit. Throws prism::Error if it is not a plain byte count.
using prism::device_memory_limit;   // core/device_memory_limit.h, shared with the other backends
}  // namespace cuda

}  // namespace prism
