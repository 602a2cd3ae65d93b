// The OpenCL C entry points: one __kernel per stage of kernels/stages.h, nothing else. Embedded in the binary at
// build time (cmake/PrismEmbedText.cmake resolves the includes) and compiled at run time by clBuildProgram.
#define RT_OPENCL
#include "stages.h"

// prism_<stage>(one __global pointer per line of kernels/data_arrays.h, uint depth) for every line of
// kernels/stage_list.h: see opencl_entry.h and backends/opencl/CMakeLists.txt. The host may build a program for some
// stages only (-D RT_CL_STAGE_MASK=<bit i: line i>: opencl_register_budgets.h); by default all.
#ifndef RT_CL_STAGE_MASK
#define RT_CL_STAGE_MASK 0xffffffffu
#endif
#include "opencl_stage_entries.h"
