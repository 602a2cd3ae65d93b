// OpenCL entry of the bandwidth copy kernel: its two buffers and the element count, then the shared function.
// Built at run time with -DRT_OPENCL from the text embedded in the program (embed_opencl.cmake).
#include "bandwidth_copy.h"

__kernel void bandwidth_copy(__global uint4* source, __global uint4* destination, uint count) {
    BandwidthBuffers kg;
    kg.bandwidth_src = source;
    kg.bandwidth_dst = destination;
    rt_bandwidth_copy(kg, count);
}
