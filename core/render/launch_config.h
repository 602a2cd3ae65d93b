// The launch shape every GPU backend uses (docs/fairness.md): a fixed grid of work-groups per compute unit (SM on
// NVIDIA), each of kWorkGroupSize invocations, and grid-stride loops over counts that live on the device.
// 32 groups per compute unit rather than one resident wave: with grid-stride loops a grid larger than what fits at
// once leaves a tail of groups that start late (a partial wave; Nsight Compute measurements in docs/fairness.md);
// many small waves make that tail short whatever each compiler's register count is.
#pragma once

namespace prism {

inline constexpr unsigned kWorkGroupsPerComputeUnit = 32;
inline constexpr unsigned kWorkGroupSize = 128;  // also `local_size_x` in shaders/common.glsl

}  // namespace prism
