// One way to render with any backend name, "cpu-ref" included: what the prism command, the tests and the
// benchmarks use. Wraps either the recursive reference renderer or a Backend driven by the wavefront Renderer.
#pragma once

#include <memory>
#include <string>

#include "core/render/backend.h"
#include "core/render/reference_renderer.h"
#include "core/render/renderer.h"

namespace prism {

// "auto" becomes the fastest backend this machine runs: cuda when a CUDA device answers, else cpu.
std::string resolve_backend_name(const std::string& requested);

// The BVH node layout to build for `backend` when "stack", "escape", "wide" or "auto" is requested. "auto" is the
// PRISM_BVH_LAYOUT environment variable when it is set, else the layout measured fastest for the backend: wide on
// the cpu backends (cpu, cpu-ref), stack on the GPU ones (every backend traces every layout).
// Throws prism::Error for an unknown name.
BvhLayout resolve_bvh_layout(const std::string& requested, const std::string& backend);
std::string bvh_layout_name(BvhLayout layout);

class RenderEngine {
public:
    // Throws prism::Error for unknown or unavailable backends (listing what is available). `gl`: the viewer's GL
    // context, to share the display buffer with (see gl_interop()); null for no interop.
    RenderEngine(const std::string& backend_name, const DeviceScene& scene, const GlContextHandles* gl = nullptr);
    ~RenderEngine();

    BackendInfo info() const;
    // The registers, stack and spill each stage's kernel got from its API's compiler (cpu-ref: none; a query that
    // fails: none, and the source says why).
    KernelResources kernel_resources() const;
    // The backend's GL interop, or why there is none (cpu-ref and cpu: the frame is already in host memory).
    GlInteropOffer gl_interop();
    FrameResult render(const Camera& camera, const RenderSettings& settings,
                       const std::function<void(double fraction)>& progress = {});
    // The rays uploaded once and traced `launches` times back to back (Renderer::trace).
    std::vector<RayHit> trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches = 1);
    // Intersect time of each launch of the last trace(): device timers where the API has them; and their sum.
    const std::vector<double>& last_launch_ms() const;
    double last_trace_ms() const;
    // Moving instances: refit (or rebuild) the top level and re-upload it.
    void update_instances(DeviceScene& scene, const std::vector<glm::mat4>& transforms, bool rebuild);
    // The scene at `seconds` into its motion (core/scene/scene_motion.h): its instances placed, the meshes its
    // animation deforms posed anew with their BVHs refitted, the top level refitted, its animated lights moved;
    // uploads what changed. `device` was built from `scene` with moving instances (SceneOptions::moving_instances).
    void move_to(const Scene& scene, DeviceScene& device, double seconds);

private:
    std::string name_;
    const DeviceScene& scene_;
    std::unique_ptr<ReferenceRenderer> reference_;
    std::unique_ptr<Backend> backend_;
    std::unique_ptr<Renderer> renderer_;
};

}  // namespace prism
