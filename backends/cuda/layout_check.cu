// The CUDA side of the layout contract: every line of kernels/layout_table.h checked by nvcc against the structs
// as kernels/types.h defines them under RT_CUDA (CUDA's own float4/uint4). A mismatch fails the build.
#include <cstddef>

#include "kernels/types.h"

#define RT_LAYOUT_STRUCT(name, size) \
    static_assert(sizeof(name) == (size), "CUDA: " #name " size differs from layout_table.h");
// Bytes of each kind of member: a float4/uint4 (16-aligned too) or a 4-byte scalar.
#define RT_LAYOUT_BYTES_f4 16
#define RT_LAYOUT_BYTES_u4 16
#define RT_LAYOUT_BYTES_f1 4
#define RT_LAYOUT_BYTES_u1 4
#define RT_LAYOUT_MEMBER(name, member, offset, kind)                                                                 \
    static_assert(offsetof(name, member) == (offset),                                                                \
                  "CUDA: " #name "." #member " offset differs from layout_table.h");                                 \
    static_assert(                                                                                                   \
        sizeof(name::member) == RT_LAYOUT_BYTES_##kind && alignof(decltype(name::member)) == RT_LAYOUT_BYTES_##kind, \
        "CUDA: " #name "." #member " is not a " #kind);                                                              \
    static_assert(alignof(name) == 16, "CUDA: " #name " is not 16-aligned");
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER

// Element types of the scalar arrays: the host and the kernels index them with the same stride.
static_assert(sizeof(uint) == 4 && sizeof(float4) == 16 && alignof(float4) == 16, "CUDA: scalar sizes");
