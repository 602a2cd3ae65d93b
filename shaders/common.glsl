// Shared preamble of every stage shader: the kernels/ headers compiled as GLSL, one work-group size for every
// stage (128, the size the CUDA and OpenCL backends launch), and the depth as a push constant.
#extension GL_GOOGLE_include_directive : require
#define RT_GLSL
#include "stages.h"

layout(local_size_x = 128) in;
layout(push_constant) uniform StagePush { uint depth; } pc;
