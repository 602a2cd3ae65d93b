// Vulkan entry of the bandwidth copy kernel: the two buffers and the element count, then the shared function.
#version 460
#extension GL_GOOGLE_include_directive : require

// Declared before the shared code: its grid loop strides by gl_WorkGroupSize, which glslang silently takes as
// (1, 1, 1) in functions defined before the local_size declaration (each element would be copied 256 times).
layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 0) readonly buffer BandwidthSource { uvec4 bandwidth_src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer BandwidthDestination { uvec4 bandwidth_dst[]; };
layout(push_constant) uniform BandwidthParams { uint count; } params;
// The accessors RT_FETCH and RT_STORE call in GLSL (kernels/compat/glsl.h).
uvec4 rt_fetch_bandwidth_src(uint i) { return bandwidth_src[i]; }
void rt_store_bandwidth_dst(uint i, uvec4 v) { bandwidth_dst[i] = v; }

#include "bandwidth_copy.h"

#if RT_BANDWIDTH_GROUP_SIZE != 256
#error "local_size_x above must equal RT_BANDWIDTH_GROUP_SIZE"
#endif

void main() { rt_bandwidth_copy(0, params.count); }
