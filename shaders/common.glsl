// Shared preamble of every stage shader: one work-group size for every stage (128, the size the CUDA and OpenCL
// backends launch), the depth as a push constant, then the kernels/ headers compiled as GLSL.
//
// The local size comes FIRST: the grid loop (kernels/compat/glsl.h) strides by gl_WorkGroupSize, and glslang
// silently compiles gl_WorkGroupSize as (1, 1, 1) in a function defined before the local_size declaration, so
// every item would be processed 128 times over (found by the shadow-ray counts of the agreement tests).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 128) in;
layout(push_constant) uniform StagePush { uint depth; } pc;

#define RT_GLSL
#include "stages.h"
