// Shared preamble of every stage shader: one work-group size for every stage (128, the size the CUDA and OpenCL
// backends launch), the push constants, then the kernels/ headers compiled as GLSL.
//
// The local size comes FIRST: the grid loop (kernels/compat/glsl.h) strides by gl_WorkGroupSize, and glslang
// silently compiles gl_WorkGroupSize as (1, 1, 1) in a function defined before the local_size declaration, so
// every item would be processed 128 times over (found by the shadow-ray counts of the agreement tests).
//
// Built twice (cmake/PrismShaders.cmake): with descriptors, each data array a storage buffer at its binding; and
// with RT_GLSL_ADDRESS, each array reached through its buffer device address, for arrays larger than the device's
// maxStorageBufferRange (lavapipe: 128 MiB). kernels/globals.h declares both.
#extension GL_GOOGLE_include_directive : require
// Queue slots are taken a subgroup at a time (kernels/compat/glsl.h, RT_QUEUE_RESERVE).
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#ifdef RT_GLSL_ADDRESS
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#endif
layout(local_size_x = 128) in;
// depth: the queue a stage works on; groups: the backend's fixed grid (the most groups a launch may have).
layout(push_constant) uniform StagePush { uint depth; uint groups; } pc;
// Whether the traversal stages take their rays a subgroup at a time from a counter (kernels/stages.h,
// RT_WORK_LOOP) or keep the grid loop. The backend sets it false on a CPU device: Mesa 22.3's lavapipe returned
// wrong or no hits for about one ray in a thousand with the taking loop, even with one atomic add per invocation
// and one thread (docs/kernels.md, "Taking rays"), and a CPU driver has no idle warp slots to fill.
layout(constant_id = 0) const bool rt_vk_take_work = true;

#define RT_GLSL
#include "vulkan_bindings.h"
// The row accessors of the structs with 4-byte members, generated from layout_table.h (kernels/globals.h).
#include "glsl_rows.h"
#ifdef RT_GLSL_ADDRESS
layout(std430, set = 0, binding = RT_VK_BINDING_ADDRESSES) readonly buffer rt_address_block { uint64_t rt_addresses[]; };
#endif

#include "stages.h"
