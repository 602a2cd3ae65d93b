// KernelGlobals: how stage code reaches the device arrays. On C++/CUDA/OpenCL it is a struct of pointers built
// from data_arrays.h; in GLSL the arrays are global buffer blocks and `kg` is a dummy int.
#ifndef RT_GLOBALS_H
#define RT_GLOBALS_H

#include "types.h"

#if defined(RT_GLSL)
#define RT_GLSL_ACCESS_ro readonly
#define RT_GLSL_ACCESS_rw
#if defined(RT_GLSL_ADDRESS)
// Address mode: each array is a buffer reference made from its 64-bit device address, which the shader preamble
// (shaders/common.glsl) declares as rt_addresses[binding]. No descriptor range limit applies; RT_FETCH and friends
// (compat/glsl.h) go through rt_array_<name>().
#define RT_DATA_ARRAY(slot, type, name, access, role)                                                         \
    layout(buffer_reference, std430, buffer_reference_align = 16) RT_GLSL_ACCESS_##access buffer name##_ref { \
        type name##_at[];                                                                                     \
    };                                                                                                        \
    name##_ref rt_array_##name() { return name##_ref(rt_addresses[slot]); }
#else
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    layout(std430, set = 0, binding = slot) RT_GLSL_ACCESS_##access buffer name##_block { type name[]; };
#endif
#include "data_arrays.h"
#undef RT_DATA_ARRAY
#define KernelGlobals int
#else
RT_STRUCT_BEGIN(KernelGlobals)
#define RT_DATA_ARRAY(slot, type, name, access, role) RT_GLOBAL_PTR_##access(type) name;
#include "data_arrays.h"
#undef RT_DATA_ARRAY
RT_STRUCT_END(KernelGlobals)
#endif

#endif
