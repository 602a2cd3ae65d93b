// The `cuda` backend: kernels/ compiled by nvcc (stages.cu), plain cudaMalloc buffers, one stream, CUDA events
// around every launch. "cuda" is device 0; "cuda:<index>" or "cuda:<name substring>" picks another.
#pragma once

#include <cstddef>
#include <string>

#include "core/render/backend.h"
#include "core/render/launch_config.h"

namespace prism {

BackendFactory cuda_backend_factory();

namespace cuda {
// Launch configuration shared by every stage (docs/fairness.md; the OpenCL backend uses the same rule):
// a fixed grid of kBlocksPerMultiprocessor x SM count blocks of kThreadsPerBlock, grid-stride loops.
inline constexpr unsigned kThreadsPerBlock = 128;
inline constexpr unsigned kBlocksPerMultiprocessor = prism::kWorkGroupsPerComputeUnit;
}  // namespace cuda

}  // namespace prism
