// The copy kernel of `prism bandwidth`: one 16-byte element per loop step over a grid loop, so the measured
// kernel-issued bandwidth is that of the same source on CUDA, OpenCL C and GLSL (kernel-issued versus
// copy-engine copies). The buffers are its own, not the ray-tracing data list: each language's thin wrapper
// (bench/bandwidth/*_copy.cu|.cl, shaders/bandwidth_copy.comp) declares them.
#ifndef RT_BANDWIDTH_COPY_H
#define RT_BANDWIDTH_COPY_H

#include "compat/compat.h"

// uint4 rather than float4: a float copy may canonicalise NaN bit patterns; an integer copy moves bits.
#if defined(RT_GLSL)
// GLSL: the wrapper declares the global blocks `bandwidth_src[]` and `bandwidth_dst[]`; the handle is a dummy.
#define BandwidthBuffers int
#else
RT_STRUCT_BEGIN(BandwidthBuffers)
    RT_GLOBAL_PTR(uint4) bandwidth_src;
    RT_GLOBAL_PTR(uint4) bandwidth_dst;
RT_STRUCT_END(BandwidthBuffers)
#endif

// Copies `count` uint4 elements from bandwidth_src to bandwidth_dst.
RT_FUNC void rt_bandwidth_copy(BandwidthBuffers kg, uint count) {
    RT_GRID_LOOP(i, count) { RT_STORE(kg, bandwidth_dst, i, RT_FETCH(kg, bandwidth_src, i)); }
}

// Threads per work-group in every language; the host sizes the grid from it.
#define RT_BANDWIDTH_GROUP_SIZE 256

#endif
