// The cpu backend's stage launches, compiled once per instruction set: the kernels/ stages are the same source,
// the compiler targets SSE2 (every x86-64 CPU) or AVX2 (8-wide BVH nodes in one register). The backend picks the
// best one the CPU runs (backends/cpu/cpu_backend.cpp). Neither contracts a*b+c into FMA, so both give the results
// the cpu-ref reference renderer gives, bit for bit.
#pragma once

#include <cstdint>

#include "core/render/backend.h"
#include "kernels/globals.h"

namespace prism::cpu {

// Runs one launch of `stage` on the calling thread's share of the grid (rt_cpu_grid).
using StageRunner = void (*)(Stage stage, KernelGlobals kg, uint32_t depth);

void run_stage_baseline(Stage stage, KernelGlobals kg, uint32_t depth);
#if defined(PRISM_CPU_AVX2)
void run_stage_avx2(Stage stage, KernelGlobals kg, uint32_t depth);
#endif

}  // namespace prism::cpu
