// The C++ side of the layout contract (kernels/layout_table.h); the other languages check the same table.
#include <cstddef>

#include <gtest/gtest.h>

#include "kernels/types.h"

#define RT_LAYOUT_STRUCT(name, size) static_assert(sizeof(name) == (size), #name " size differs from layout_table.h");
#define RT_LAYOUT_BYTES_f4 16
#define RT_LAYOUT_BYTES_u4 16
#define RT_LAYOUT_BYTES_f1 4
#define RT_LAYOUT_BYTES_u1 4
#define RT_LAYOUT_MEMBER(name, member, offset, kind)                                                            \
    static_assert(offsetof(name, member) == (offset), #name "." #member " offset differs from layout_table.h"); \
    static_assert(sizeof(name::member) == RT_LAYOUT_BYTES_##kind, #name "." #member " is not a " #kind);        \
    static_assert(alignof(name) == 16, #name " is not 16-aligned");
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER

TEST(Layout, EveryDeviceArrayStructIsInTheTable) {
    // Each element type of kernels/data_arrays.h is either a scalar/float4 or listed in layout_table.h.
    int listed = 0;
#define RT_LAYOUT_STRUCT(name, size) ++listed;
#define RT_LAYOUT_MEMBER(name, member, offset, kind)
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER
    int structs = 0;
#define RT_DATA_ARRAY(slot, type, name, access, role) structs += sizeof(type) % 16 == 0 && sizeof(type) >= 16;
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    EXPECT_GE(listed, structs - 1);  // radiance is a bare float4, not a struct
    EXPECT_EQ(listed, 15);
}
