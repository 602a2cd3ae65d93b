// The seam between the host half of the cuda backend and the nvcc-compiled stages (stages.cu). Plain types only:
// no CUDA header and no kernels/ header may be seen by both sides (each defines its own float4).
#pragma once

namespace prism::cuda {

// Launches stage `stage` (prism::Stage order) with `blocks` x `threads` on `stream` (a cudaStream_t).
// `arrays` holds one device pointer per line of kernels/data_arrays.h, indexed by slot.
// Returns the cudaError_t of the launch (0 = cudaSuccess); errors inside the kernel surface at the next sync.
int launch_stage(unsigned stage, void* const* arrays, unsigned depth, unsigned blocks, unsigned threads, void* stream);

// What ptxas gave stage `stage`'s kernel (cudaFuncGetAttributes): registers per thread, local bytes per thread
// (stack and spills), static shared bytes per block. Returns the cudaError_t (0 = cudaSuccess).
struct StageAttributes {
    int registers = 0;
    long long local_bytes = 0;
    long long shared_bytes = 0;
};
int stage_attributes(unsigned stage, StageAttributes* out);

}  // namespace prism::cuda
