// The stages compiled for AVX2 (backends/cpu/CMakeLists.txt gives this file -mavx2 -ffp-contract=off), run when
// the CPU has it.
#define PRISM_CPU_STAGE_RUNNER run_stage_avx2
#include "backends/cpu/cpu_stages_impl.h"
