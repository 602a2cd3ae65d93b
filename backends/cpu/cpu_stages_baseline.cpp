// The stages for any x86-64 CPU (SSE2), or for the build's target elsewhere.
#define PRISM_CPU_STAGE_RUNNER run_stage_baseline
#include "backends/cpu/cpu_stages_impl.h"
