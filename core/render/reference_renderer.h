// `cpu-ref`: the seed's canonical recursive Whitted tracer (thesis 6.3), multithreaded over tiles. It calls the
// same kernels/ functions as the wavefront stages (intersection, traversal, shading, accumulation) but follows
// each ray's children depth-first by recursion instead of through device queues, so comparing it with the
// wavefront backends tests their scheduling, queues and weights: the oracle of the agreement tests.
#pragma once

#include <functional>

#include "core/render/device_scene.h"
#include "core/render/renderer.h"

namespace prism {

class ReferenceRenderer {
public:
    explicit ReferenceRenderer(const DeviceScene& scene, unsigned threads = 0);
    FrameResult render(const Camera& camera, const RenderSettings& settings,
                       const std::function<void(double fraction)>& progress = {});
    // `launches` times over the rays (Renderer::trace); the host clock times each.
    std::vector<RayHit> trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches = 1);
    const std::vector<double>& last_launch_ms() const { return last_launch_ms_; }

private:
    std::vector<double> last_launch_ms_;
    const DeviceScene& scene_;
    unsigned threads_;
};

}  // namespace prism
