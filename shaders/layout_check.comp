// The GLSL side of the layout contract (kernels/layout_table.h), run by tests/test_vulkan_backend.cpp.
// Every device array of kernels/data_arrays.h is declared as the stages declare it (std430, same binding; not
// readonly here, so it can be written), and elements 0 and 1 get a marker in every 4-byte word: the value
// binding * 1000 + element * 500 + (the word index the table gives the member, + component). The host reads the
// bytes back: a member GLSL places elsewhere, or an array stride other than the table's size, shows up as a
// wrong marker.
#version 460
#extension GL_GOOGLE_include_directive : require
#define RT_GLSL
#include "types.h"

layout(local_size_x = 1) in;

#define RT_DATA_ARRAY(slot, type, name, access, role) \
    layout(std430, set = 0, binding = slot) buffer name##_block { type name[]; };
#include "data_arrays.h"
#undef RT_DATA_ARRAY

vec4 rt_marker_f4(uint word) { return vec4(float(word), float(word + 1u), float(word + 2u), float(word + 3u)); }
uvec4 rt_marker_u4(uint word) { return uvec4(word, word + 1u, word + 2u, word + 3u); }
float rt_marker_f1(uint word) { return float(word); }
uint rt_marker_u1(uint word) { return word; }

// One function per struct of the table: rt_mark_<struct>(element, marker base).
void rt_mark_none_() {
#define RT_LAYOUT_STRUCT(name, size) } void rt_mark_##name(inout name v, uint base) {
#define RT_LAYOUT_MEMBER(name, member, offset, kind) v.member = rt_marker_##kind(base + uint(offset) / 4u);
#include "layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER
}
// The scalar and vector arrays.
void rt_mark_uint(inout uint v, uint base) { v = base; }
void rt_mark_float4(inout vec4 v, uint base) { v = rt_marker_f4(base); }

void main() {
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    rt_mark_##type(name[0], uint(slot) * 1000u); \
    rt_mark_##type(name[1], uint(slot) * 1000u + 500u);
#include "data_arrays.h"
#undef RT_DATA_ARRAY
}
