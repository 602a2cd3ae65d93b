// kernels/ compiled by nvcc (RT_CUDA): one __global__ entry per stage, and the launch the host half calls.
// The entry points are one line each; every decision is in kernels/stages.h.
#include <cuda_runtime.h>

#include <string_view>

#include "backends/cuda/cuda_launch.h"
#include "kernels/stages.h"

// Register budgets for blocks of 128 threads (kThreadsPerBlock, cuda_backend.h), a launch setting: the traversal
// stages are latency-bound, and ptxas left to itself gave intersect a few registers over 64, so that 7 blocks
// instead of 8 fit on an SM; asking for 8 keeps intersect, occlude and shadow at 64 (docs/kernels.md, "Edges"). The
// other stages (0) take what ptxas chooses.
constexpr unsigned min_resident_blocks(std::string_view stage) {
    if (stage == "intersect_mesh" || stage == "occlude_mesh") return 9u;  // the one-mesh walk fits 56 registers
    return stage == "intersect" || stage == "occlude" || stage == "shadow" ? 8u : 0u;
}

// prism_cuda_<name>: one __global__ entry per line of kernels/stage_list.h.
#define RT_STAGE(name, Name, pass, launch, needs)                      \
    __global__ void __launch_bounds__(128, min_resident_blocks(#name)) \
        prism_cuda_##name(KernelGlobals kg, uint depth) {              \
        rt_kernel_##name(kg, depth);                                   \
    }
#include "kernels/stage_list.h"
#undef RT_STAGE

namespace prism::cuda {

int launch_stage(unsigned stage, void* const* arrays, unsigned depth, unsigned blocks, unsigned threads, void* stream) {
    // The pointer table is in data_arrays.h order (slot = binding), so the X-macro fills KernelGlobals.
    KernelGlobals kg;
#define RT_DATA_ARRAY(slot, type, name, access, role) kg.name = static_cast<type*>(arrays[slot]);
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    cudaStream_t s = static_cast<cudaStream_t>(stream);
    // Stage i is line i of kernels/stage_list.h.
    enum : unsigned {
#define RT_STAGE(name, Name, pass, launch, needs) stage_##name,
#include "kernels/stage_list.h"
#undef RT_STAGE
    };
    switch (stage) {
#define RT_STAGE(name, Name, pass, launch, needs)                \
    case stage_##name:                                           \
        prism_cuda_##name<<<blocks, threads, 0, s>>>(kg, depth); \
        break;
#include "kernels/stage_list.h"
#undef RT_STAGE
        default: return static_cast<int>(cudaErrorInvalidValue);
    }
    return static_cast<int>(cudaGetLastError());
}

int stage_attributes(unsigned stage, StageAttributes* out) {
    enum : unsigned {
#define RT_STAGE(name, Name, pass, launch, needs) stage_##name,
#include "kernels/stage_list.h"
#undef RT_STAGE
    };
    cudaFuncAttributes attributes{};
    cudaError_t status = cudaErrorInvalidValue;
    switch (stage) {
#define RT_STAGE(name, Name, pass, launch, needs)                       \
    case stage_##name:                                                  \
        status = cudaFuncGetAttributes(&attributes, prism_cuda_##name); \
        break;
#include "kernels/stage_list.h"
#undef RT_STAGE
        default: break;
    }
    if (status != cudaSuccess) return static_cast<int>(status);
    out->registers = attributes.numRegs;
    out->local_bytes = static_cast<long long>(attributes.localSizeBytes);
    out->shared_bytes = static_cast<long long>(attributes.sharedSizeBytes);
    return 0;
}

}  // namespace prism::cuda
