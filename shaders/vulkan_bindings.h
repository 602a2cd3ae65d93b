// Vulkan bindings beyond kernels/data_arrays.h (whose arrays take bindings 0 .. count - 1). Included by the
// shaders and by backends/vulkan, which checks that the first one follows the last data array.
#ifndef PRISM_VULKAN_BINDINGS_H
#define PRISM_VULKAN_BINDINGS_H

#define RT_VK_BINDING_LAUNCH_ARGS 20   // uint4 per launch: vkCmdDispatchIndirect arguments (kernels/launch_args.h)
#define RT_VK_BINDING_ADDRESSES 21     // uint64 per data array: buffer device addresses (address mode only)

#endif
