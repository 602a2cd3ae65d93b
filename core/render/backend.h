// The Backend interface: memory, launches and timers, nothing else. All ray-tracing logic is in kernels/; the
// order of stages is in core/render/renderer.cpp. A backend implements this for one API (cpu, cuda, opencl, vulkan).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/render/gl_interop.h"
#include "kernels/types.h"

namespace prism {

// One id per line of kernels/data_arrays.h, equal to its Vulkan binding.
enum class DeviceArray : uint32_t {
#define RT_DATA_ARRAY(slot, type, name, access, role) name = slot,
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    Count
};
inline constexpr size_t device_array_count = static_cast<size_t>(DeviceArray::Count);
const char* device_array_name(DeviceArray array);
size_t device_array_element_size(DeviceArray array);
// The last column of kernels/data_arrays.h (which explains the roles).
enum class DeviceArrayRole { Scene, Frame, Queue, Pixel };
DeviceArrayRole device_array_role(DeviceArray array);

// Inside an RT_DATA_ARRAY definition: PRISM_IF_SCENE_ARRAY(role, code) is `code` for the scene arrays and nothing
// for the others, so DeviceScene's fields, their upload and host_globals come from the same list.
#define PRISM_IF_SCENE_ARRAY(role, ...) PRISM_IF_SCENE_ARRAY_##role(__VA_ARGS__)
#define PRISM_IF_SCENE_ARRAY_scene(...) __VA_ARGS__
#define PRISM_IF_SCENE_ARRAY_frame(...)
#define PRISM_IF_SCENE_ARRAY_queue(...)
#define PRISM_IF_SCENE_ARRAY_pixel(...)

// The stages of kernels/stage_list.h, in frame order.
enum class Stage : uint32_t {
#define RT_STAGE(name, Name, pass, launch, needs) Name,
#include "kernels/stage_list.h"
#undef RT_STAGE
    Count
};
inline constexpr size_t stage_count = static_cast<size_t>(Stage::Count);
// When a stage runs in the frame, and over how many items (kernels/stage_list.h explains both).
enum class StagePass { Before, Bounce, After };
enum class StageLaunch { Grid, GridSizesQueue, Queue, QueueGrows };
const char* stage_name(Stage stage);
StagePass stage_pass(Stage stage);
StageLaunch stage_launch(Stage stage);
// The RT_FLAG_* bit a frame needs for the stage to be launched (0: every frame), and whether a frame with these
// flags launches it.
uint32_t stage_needs(Stage stage);
inline bool stage_runs(Stage stage, uint32_t frame_flags) {
    return (frame_flags & stage_needs(stage)) == stage_needs(stage);
}

struct StageTiming {
    Stage stage;
    uint32_t depth;
    double milliseconds;  // device time (GPU timestamps) where the API has it
};

struct BackendInfo {
    std::string name;          // "cpu", "cuda", "opencl", "vulkan"
    std::string device;        // e.g. "NVIDIA H100 80GB HBM3", "pthread-...", "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string driver;        // driver version string
    std::string api_version;   // e.g. "CUDA 13.0", "OpenCL 3.0 CUDA", "Vulkan 1.3.239"
    size_t device_memory = 0;  // bytes
    size_t max_buffer = 0;     // largest single buffer, bytes
};

// What one stage's compiled kernel takes on the device, as the API reports it after compiling: the same source
// gets a register count, stack and spill from each API's compiler, and these decide how many threads run at once
// (docs/kernels.md). -1: the API does not say.
struct StageResources {
    Stage stage = Stage::Count;
    int registers = -1;            // per thread
    long long private_bytes = -1;  // per thread: stack, local arrays and spills
    long long shared_bytes = -1;   // per work-group, static
    // Everything the API reported, by its own names (Vulkan's pipeline executable statistics; empty elsewhere).
    std::vector<std::pair<std::string, std::string>> statistics;
};

// A backend's StageResources, one per stage it compiled, and how they were read.
struct KernelResources {
    std::string source;  // e.g. "cudaFuncGetAttributes"; or why there are none
    std::vector<StageResources> stages;
};

class Backend {
public:
    virtual ~Backend() = default;
    virtual BackendInfo info() const = 0;
    virtual KernelResources kernel_resources() const { return {"not reported by this backend", {}}; }

    // Memory. (Re)allocates when the size changes; contents are undefined after a reallocation. Sizes above
    // info().max_buffer or the free device memory throw prism::Error naming the array and the limit.
    virtual void allocate(DeviceArray array, size_t bytes) = 0;
    // Ordered with the stages enqueued before them (an in-order queue).
    virtual void write(DeviceArray array, const void* data, size_t bytes, size_t offset = 0) = 0;
    virtual void read(DeviceArray array, void* data, size_t bytes, size_t offset = 0) = 0;
    // Reads the array's first `bytes` into host memory the device writes at the bus's speed (page-locked or
    // mapped, owned by the backend and kept from call to call) and returns it: valid until the next read_pinned
    // of the same array or the backend's end. A frame's image comes back this way; into pageable memory, as
    // read() writes, each API stages the copy at a fraction of that speed (docs/results.md has both).
    virtual const void* read_pinned(DeviceArray array, size_t bytes) = 0;
    virtual void zero(DeviceArray array) = 0;

    // Launches. A stage processes every item of its queue (the count lives on the device); `depth` selects the
    // queue. Asynchronous: finish() waits and returns the timings of the stages enqueued since the last finish.
    virtual void enqueue(Stage stage, uint32_t depth) = 0;
    virtual std::vector<StageTiming> finish() = 0;

    // Display interop with the viewer's GL context (core/render/gl_interop.h). Only a backend created with
    // GlContextHandles offers one; otherwise, or when its driver cannot share with that context, the reason.
    virtual GlInteropOffer gl_interop() { return {nullptr, "no GL interop for this backend"}; }
};

// Backend names as users write them: "cpu", "cuda", "opencl:pocl", "vulkan:nvidia". The part after the colon
// selects a device by case-insensitive substring of its platform/device name.
struct BackendSpec {
    std::string api;
    std::string device_filter;
};
BackendSpec parse_backend_spec(const std::string& text);

struct BackendAvailability {
    std::string name;  // "cpu", "cuda", ...
    bool available = false;
    std::string detail;  // devices found, or why the backend is unavailable
    std::vector<std::string> devices;
};

// Each enabled backend registers one of these (backends/backend_list.cpp). `gl`, when not null, asks for GL
// interop with that context (the viewer): the backend sets up what its API needs at creation (the OpenCL context
// must be created with the GL context) and says through gl_interop() whether it could. Failing to share is not
// an error: the viewer falls back to the host copy.
struct BackendFactory {
    std::string name;
    std::function<std::unique_ptr<Backend>(const std::string& device_filter, const GlContextHandles* gl)>
        create;  // throws prism::Error
    std::function<BackendAvailability()> probe;
};

void register_backend(BackendFactory factory);
const std::vector<BackendFactory>& registered_backends();
// Creates the backend named by `spec` ("cpu-ref" is not a Backend: see reference_renderer.h). Unknown or
// unavailable names throw prism::Error listing what is available.
std::unique_ptr<Backend> create_backend(const std::string& spec, const GlContextHandles* gl = nullptr);

}  // namespace prism
