// The Vulkan entry point of one stage of kernels/stage_list.h. backends/vulkan/CMakeLists.txt writes a
// <stage>.comp per list line that defines RT_VK_STAGE_KERNEL (rt_kernel_<stage>, kernels/stages.h) and
// RT_VK_SIZES_QUEUE (1 for the GridSizesQueue stages) and includes this file.
#include "common.glsl"
#if RT_VK_SIZES_QUEUE
// The queue counts are final when this stage runs: it writes the launch arguments of the indirect stages after it
// in passing (shaders/launch_args.glsl).
#include "launch_args.glsl"
#endif

void main() {
#if RT_VK_SIZES_QUEUE
    rt_vk_fill_launch_args();
#endif
    RT_VK_STAGE_KERNEL(0, pc.depth);
}
