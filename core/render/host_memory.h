// The host memory a frame needs, checked before anything is allocated: a 16384x16384 frame on cpu-ref otherwise
// grows until the machine stops it. PRISM_HOST_MEMORY_LIMIT (bytes) lowers the limit, as PRISM_DEVICE_MEMORY_LIMIT
// does for devices, so tests can exercise the refusal without filling a machine.
#pragma once

#include <cstdint>
#include <string>

#include "core/render/renderer.h"

namespace prism {

// The limit: PRISM_HOST_MEMORY_LIMIT when set, else the machine's physical memory, lowered to the address-space
// limit (RLIMIT_AS) when one is set. Throws prism::Error when the variable is not a byte count.
uint64_t host_memory_limit();

// Where a backend keeps its frame arrays: the wavefront queues and accumulation in host memory (cpu), the
// recursive reference's accumulation in host memory (cpu-ref), or everything on a device (cuda, opencl, vulkan).
enum class FrameArrays { HostWavefront, HostReference, Device };

// Bytes of host memory one frame of `settings` needs beyond the scene: the result Prism keeps and encodes, plus
// the frame arrays when they live in host memory (with one light's shadow queue, the least a scene has).
// `backend` as the user spells it ("cpu-ref", "opencl:pocl"): FrameArrays by its API; "auto" counts as cpu.
uint64_t frame_host_bytes(const RenderSettings& settings, FrameArrays arrays);
FrameArrays frame_arrays_of(const std::string& backend);

// Throws prism::Error "<what>: needs about N MiB of host memory, over the limit of M MiB (...)" when `bytes` is
// over host_memory_limit().
void check_host_memory(uint64_t bytes, const std::string& what);

}  // namespace prism
