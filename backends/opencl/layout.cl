// The OpenCL side of the layout contract (kernels/layout_table.h): writes, in table order, each struct's size and
// each member's offset as OpenCL C lays them out (pointer arithmetic on a private instance). The test compares
// the words with the table (tests/test_opencl_backend.cpp).
#define RT_OPENCL
#include "types.h"

__kernel void rt_layout(__global uint* out) {
    if (get_global_id(0) != 0) return;
    uint i = 0u;
#define RT_LAYOUT_STRUCT(name, size) out[i++] = (uint)sizeof(name);
#define RT_LAYOUT_MEMBER(name, member, offset, kind)                                  \
    {                                                                                 \
        name probe;                                                                   \
        out[i++] = (uint)((__private char*)&probe.member - (__private char*)&probe); \
    }
#include "layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER
}
