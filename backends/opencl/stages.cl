// The OpenCL C entry points: one __kernel per stage of kernels/stages.h, nothing else. Embedded in the binary at
// build time (cmake/PrismEmbedText.cmake resolves the includes) and compiled at run time by clBuildProgram.
#define RT_OPENCL
#include "stages.h"

// prism_<stage>(one __global pointer per line of kernels/data_arrays.h, uint depth): see opencl_entry.h.
#define RT_CL_STAGE generate
#include "opencl_entry.h"
#define RT_CL_STAGE intersect
#include "opencl_entry.h"
#define RT_CL_STAGE miss
#include "opencl_entry.h"
#define RT_CL_STAGE shade
#include "opencl_entry.h"
#define RT_CL_STAGE shadow
#include "opencl_entry.h"
#define RT_CL_STAGE resolve
#include "opencl_entry.h"
