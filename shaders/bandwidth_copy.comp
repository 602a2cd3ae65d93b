// Vulkan entry of the bandwidth copy kernel: the two buffers and the element count, then the shared function.
#version 460
#extension GL_GOOGLE_include_directive : require

// First, before any code: glslang gives gl_WorkGroupSize (used by RT_GRID_LOOP's stride) the value declared
// so far, so a later declaration leaves functions above it with a stride of 1 (every thread redoes the work).
layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 0) readonly buffer BandwidthSource { uvec4 bandwidth_src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer BandwidthDestination { uvec4 bandwidth_dst[]; };
layout(push_constant) uniform BandwidthParams { uint count; } params;

#include "bandwidth_copy.h"

#if RT_BANDWIDTH_GROUP_SIZE != 256
#error "local_size_x above must equal RT_BANDWIDTH_GROUP_SIZE (the host sizes the grid from it)"
#endif

void main() { rt_bandwidth_copy(0, params.count); }
