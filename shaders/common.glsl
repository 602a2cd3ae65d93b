// Shared preamble of every stage shader: the kernels/ headers compiled as GLSL, one work-group size for every
// stage (128, the size the CUDA and OpenCL backends launch), and the depth as a push constant.
#extension GL_GOOGLE_include_directive : require
#define RT_GLSL
// Declared before the stage code: glslang gives gl_WorkGroupSize the size declared so far, so a later declaration
// would leave RT_GRID_LOOP striding by 1 (every invocation redoing the work, correct but ~128x slower).
layout(local_size_x = 128) in;
#include "stages.h"
layout(push_constant) uniform StagePush { uint depth; } pc;
