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
    std::vector<RayHit> trace(std::span<const RayQuery> rays, bool any_hit);
    double last_trace_ms() const { return last_trace_ms_; }

private:
    double last_trace_ms_ = 0.0;
    const DeviceScene& scene_;
    unsigned threads_;
};

}  // namespace prism
