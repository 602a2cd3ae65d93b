// Vulkan bindings beyond kernels/data_arrays.h, whose arrays take bindings 0 .. count - 1: these follow them, so an
// array added to the list moves them by itself. Included by the shaders and by backends/vulkan.
#ifndef PRISM_VULKAN_BINDINGS_H
#define PRISM_VULKAN_BINDINGS_H

// The number of lines of data_arrays.h, counted by the preprocessor (a constant expression in both languages: GLSL
// takes it in layout(binding = ...)).
#if defined(RT_GLSL)
const int rt_vk_data_array_count = 0
#else
#include <cstdint>
inline constexpr uint32_t rt_vk_data_array_count = 0
#endif
#define RT_DATA_ARRAY(slot, type, name, access, role) +1
#if defined(RT_GLSL)
#include "data_arrays.h"
#else
#include "kernels/data_arrays.h"
#endif
#undef RT_DATA_ARRAY
    ;

#define RT_VK_BINDING_LAUNCH_ARGS (rt_vk_data_array_count)    // uint4 per launch: vkCmdDispatchIndirect arguments
#define RT_VK_BINDING_ADDRESSES (rt_vk_data_array_count + 1)  // uint64 per data array: buffer device addresses

#endif
