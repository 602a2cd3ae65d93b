// KernelGlobals: how stage code reaches the device arrays. On C++/CUDA/OpenCL it is a struct of pointers built
// from data_arrays.h; in GLSL the arrays are global buffer blocks and `kg` is a dummy int.
#ifndef RT_GLOBALS_H
#define RT_GLOBALS_H

#include "types.h"

#if defined(RT_GLSL)
#define RT_GLSL_ACCESS_ro readonly
#define RT_GLSL_ACCESS_rw
// Every array is also declared as a second view of the same memory, `<name>_rows`: its elements as 16-byte uvec4
// rows. RT_FETCH and RT_STORE (compat/glsl.h) call rt_fetch_<name> and rt_store_<name>, which move the elements of
// a struct with 4-byte members row by row (the RT_GLSL_FETCH_/STORE_<struct> macros, generated from layout_table.h
// by cmake/PrismGlslRows.cmake and included by shaders/common.glsl) and all others as declared (below).
#define RT_GLSL_FETCH_uint(v, plain, rows, i) v = plain[(i)];
#define RT_GLSL_STORE_uint(v, plain, rows, i) plain[(i)] = (v);
#define RT_GLSL_FETCH_vec4(v, plain, rows, i) v = plain[(i)];  // float4: expanded to its GLSL name by then
#define RT_GLSL_STORE_vec4(v, plain, rows, i) plain[(i)] = (v);
// The accessors of one array; a readonly array has no store (GLSL rejects a write to it even in an unused function).
#define RT_GLSL_STORE_FUNCTION_ro(type, plain, rows, name)
#define RT_GLSL_STORE_FUNCTION_rw(type, plain, rows, name) \
    void rt_store_##name(uint i, type v) { RT_GLSL_STORE_##type(v, plain, rows, i) }
#define RT_GLSL_ACCESSORS(type, plain, rows, name, access) \
    type rt_fetch_##name(uint i) {                         \
        type v;                                            \
        RT_GLSL_FETCH_##type(v, plain, rows, i) return v;  \
    }                                                      \
    RT_GLSL_STORE_FUNCTION_##access(type, plain, rows, name)
#if defined(RT_GLSL_ADDRESS)
// Address mode: each array is a buffer reference made from its 64-bit device address, which the shader preamble
// (shaders/common.glsl) declares as rt_addresses[binding]. No descriptor range limit applies.
#define RT_DATA_ARRAY(slot, type, name, access, role)                                                              \
    layout(buffer_reference, std430, buffer_reference_align = 16) RT_GLSL_ACCESS_##access buffer name##_ref {      \
        type name##_at[];                                                                                          \
    };                                                                                                             \
    layout(buffer_reference, std430, buffer_reference_align = 16) RT_GLSL_ACCESS_##access buffer name##_rows_ref { \
        uvec4 name##_rows_at[];                                                                                    \
    };                                                                                                             \
    name##_ref rt_array_##name() { return name##_ref(rt_addresses[slot]); }                                        \
    RT_GLSL_ACCESSORS(type, rt_array_##name().name##_at, name##_rows_ref(rt_addresses[slot]).name##_rows_at, name, \
                      access)
#else
#define RT_DATA_ARRAY(slot, type, name, access, role)                                                                  \
    layout(std430, set = 0, binding = slot) RT_GLSL_ACCESS_##access buffer name##_block { type name[]; };              \
    layout(std430, set = 0, binding = slot) RT_GLSL_ACCESS_##access buffer name##_rows_block { uvec4 name##_rows[]; }; \
    RT_GLSL_ACCESSORS(type, name, name##_rows, name, access)
#endif
#include "data_arrays.h"
#undef RT_DATA_ARRAY
RT_GLSL_RESERVE_FUNCTION(counters)
RT_GLSL_TAKE_FUNCTION(counters)
#define KernelGlobals int
#else
RT_STRUCT_BEGIN(KernelGlobals)
#define RT_DATA_ARRAY(slot, type, name, access, role) RT_GLOBAL_PTR_##access(type) name;
#include "data_arrays.h"
#undef RT_DATA_ARRAY
RT_STRUCT_END(KernelGlobals)
#endif

#endif
