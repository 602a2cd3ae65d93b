// The OpenCL C entry points: one __kernel per stage of kernels/stages.h, nothing else. Embedded in the binary at
// build time (cmake/PrismEmbedText.cmake resolves the includes) and compiled at run time by clBuildProgram.
#define RT_OPENCL
#include "stages.h"

// prism_<stage>(one __global pointer per line of kernels/data_arrays.h, uint depth) for every line of
// kernels/stage_list.h: see opencl_entry.h and backends/opencl/CMakeLists.txt.
#include "opencl_stage_entries.h"
