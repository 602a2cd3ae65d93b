// Selects the one compat header for the language this translation unit is compiled as.
// The build defines exactly one of RT_CPU, RT_CUDA, RT_OPENCL, RT_GLSL; nothing is auto-detected.
#ifndef RT_COMPAT_H
#define RT_COMPAT_H

#if defined(RT_CPU) + defined(RT_CUDA) + defined(RT_OPENCL) + defined(RT_GLSL) != 1
#error "define exactly one of RT_CPU, RT_CUDA, RT_OPENCL, RT_GLSL"
#endif

// Included relative to this file, so no language needs kernels/ itself on its include path (for nvcc it must
// not be: CUDA's <math.h> would find kernels/math.h).
#if defined(RT_CPU)
#include "cpu.h"
#elif defined(RT_CUDA)
#include "cuda.h"
#elif defined(RT_OPENCL)
#include "opencl.h"
#else
#include "glsl.h"
#endif

#endif
