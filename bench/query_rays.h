// The ray sets the ray-query benchmarks trace (`prism rays --bench`, `prism bench --embree`, the Embree oracle
// tests) and how two backends' hits are compared. Primary rays come through a pinhole camera; diffuse rays leave
// their hit points cosine-distributed about the geometric normal, so they are as incoherent as a path tracer's
// first bounce.
#pragma once

#include <cstdint>
#include <vector>

#include "core/render/renderer.h"
#include "core/scene/scene.h"

namespace prism::bench {

// `count` rays on a square-ish grid through the scene camera's view.
std::vector<RayQuery> scene_camera_rays(const Scene& scene, size_t count);
// One ray per pixel centre of a width x height image from a camera on +z looking down -z at the centre of the
// scene's bounds, a 45-degree vertical field of view framing the bounding box (the mesh as loaded, no scene camera
// needed: the same rays for a PLY file on any tool).
std::vector<RayQuery> framing_camera_rays(const Scene& scene, uint32_t width, uint32_t height);
// For the primary rays that hit (`hits[i]` for `primary[i]`), in turn and round again until `count` rays exist,
// one cosine-distributed ray about the hit triangle's geometric normal (facing the incoming ray), starting just off
// the surface. Empty when no primary ray hit.
std::vector<RayQuery> diffuse_rays(const Scene& scene, const std::vector<RayQuery>& primary,
                                   const std::vector<RayHit>& hits, size_t count, uint32_t seed);
// The order that groups rays likely to visit the same nodes (Garanzha & Loop 2010's ray hash, as a sort): by
// direction octant, then along a Morton curve through the origins' bounding box (10 bits an axis); rays with one
// key keep their order. Returns the indices of `rays` in that order.
std::vector<size_t> coherent_order(const std::vector<RayQuery>& rays);
// Meister et al. 2020's two-point key, as a sort: the origin and a point a quarter of the origins' bounding-box
// diagonal along the ray (1 along it when all share one origin), both quantized to 10 bits an axis in that box
// (grown to hold both), interleaved into one 60-bit Morton code; rays with one key keep their order.
std::vector<size_t> two_point_order(const std::vector<RayQuery>& rays);

struct Agreement {
    size_t rays = 0;
    size_t same = 0;                 // same instance and primitive, or both miss
    size_t t_outside_tolerance = 0;  // same primitive but t differs by more than 1e-4 relative
    double fraction() const { return rays ? double(same) / double(rays) : 0.0; }
};
Agreement compare_hits(const std::vector<RayHit>& a, const std::vector<RayHit>& b);

}  // namespace prism::bench
