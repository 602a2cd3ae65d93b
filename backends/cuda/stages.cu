// kernels/ compiled by nvcc (RT_CUDA): one __global__ entry per stage, and the launch the host half calls.
// The entry points are one line each; every decision is in kernels/stages.h.
#include <cuda_runtime.h>

#include "backends/cuda/cuda_launch.h"
#include "kernels/stages.h"

#define PRISM_CUDA_STAGE(stage) \
    __global__ void prism_cuda_##stage(KernelGlobals kg, uint depth) { rt_kernel_##stage(kg, depth); }
PRISM_CUDA_STAGE(generate)
PRISM_CUDA_STAGE(intersect)
PRISM_CUDA_STAGE(miss)
PRISM_CUDA_STAGE(shade)
PRISM_CUDA_STAGE(shadow)
PRISM_CUDA_STAGE(resolve)
#undef PRISM_CUDA_STAGE

namespace prism::cuda {

int launch_stage(unsigned stage, void* const* arrays, unsigned depth, unsigned blocks, unsigned threads,
                 void* stream) {
    // The pointer table is in data_arrays.h order (slot = binding), so the X-macro fills KernelGlobals.
    KernelGlobals kg;
#define RT_DATA_ARRAY(slot, type, name, access) kg.name = static_cast<type*>(arrays[slot]);
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    cudaStream_t s = static_cast<cudaStream_t>(stream);
    switch (stage) {
        case 0: prism_cuda_generate<<<blocks, threads, 0, s>>>(kg, depth); break;
        case 1: prism_cuda_intersect<<<blocks, threads, 0, s>>>(kg, depth); break;
        case 2: prism_cuda_miss<<<blocks, threads, 0, s>>>(kg, depth); break;
        case 3: prism_cuda_shade<<<blocks, threads, 0, s>>>(kg, depth); break;
        case 4: prism_cuda_shadow<<<blocks, threads, 0, s>>>(kg, depth); break;
        case 5: prism_cuda_resolve<<<blocks, threads, 0, s>>>(kg, depth); break;
        default: return static_cast<int>(cudaErrorInvalidValue);
    }
    return static_cast<int>(cudaGetLastError());
}

}  // namespace prism::cuda
