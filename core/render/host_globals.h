// KernelGlobals over host memory, for code that runs kernels/ functions on the CPU outside a backend: the recursive
// reference renderer and the kernel tests. The scene arrays are used in place; the frame and pixel arrays are the
// caller's (null where the caller runs no stage that writes them).
#pragma once

#include "core/render/device_scene.h"
#include "kernels/globals.h"

namespace prism {

KernelGlobals host_globals(const DeviceScene& scene, FrameParams* frame, uint32_t* accum = nullptr,
                           uint32_t* image = nullptr, float4* radiance = nullptr);

}  // namespace prism
