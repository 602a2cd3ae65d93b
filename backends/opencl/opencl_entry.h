// One __kernel entry point for the stage named by RT_CL_STAGE (no include guard: included once per stage).
// Its parameters come from kernels/data_arrays.h (argument i = binding i), then `uint depth`; the body builds
// KernelGlobals from them and runs the whole launch, rt_kernel_<stage> (a grid-stride loop).
#define RT_CL_PASTE_(a, b) a##b
#define RT_CL_PASTE(a, b) RT_CL_PASTE_(a, b)

__kernel void RT_CL_PASTE(prism_, RT_CL_STAGE)(
#define RT_DATA_ARRAY(slot, type, name, access, role) __global type *name,
#include "data_arrays.h"
#undef RT_DATA_ARRAY
    uint depth) {
    KernelGlobals kg;
#define RT_DATA_ARRAY(slot, type, name, access, role) kg.name = name;
#include "data_arrays.h"
#undef RT_DATA_ARRAY
    RT_CL_PASTE(rt_kernel_, RT_CL_STAGE)(kg, depth);
}

#undef RT_CL_STAGE
