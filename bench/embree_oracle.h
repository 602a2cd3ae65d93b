// Embree (Intel's CPU ray tracer, Debian libembree-dev) as an independent oracle and speed reference: the tests
// compare Prism's hits with it, the benchmark compares throughput. Also the ray set both use: primary rays from the
// scene camera plus cosine-distributed diffuse rays from their hit points (bench/query_rays.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bench/query_rays.h"
#include "core/render/renderer.h"
#include "core/scene/scene.h"
#include "core/util/non_copyable.h"

namespace prism::oracle {

class EmbreeScene : private NonCopyable {
public:
    explicit EmbreeScene(const Scene& scene, unsigned threads = 0);  // every instance, world space
    ~EmbreeScene();

    // Closest hits with rtcIntersect1 (one ray at a time) or rtcIntersect8 (packets), on `threads` threads.
    std::vector<RayHit> intersect1(const std::vector<RayQuery>& rays) const;
    std::vector<RayHit> intersect8(const std::vector<RayQuery>& rays) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// `primary` camera rays on a square-ish grid through the scene camera's view, then for every primary hit
// (found with `embree`) cosine-distributed diffuse rays from the hit point until `total` rays exist.
struct OracleRays {
    std::vector<RayQuery> rays;
    size_t primary = 0;
    size_t diffuse = 0;
};
OracleRays make_oracle_rays(const Scene& scene, const EmbreeScene& embree, size_t primary, size_t total, uint32_t seed);

// The comparison of two hit lists (bench/query_rays.h), here for the oracle's users.
using bench::Agreement;
using bench::compare_hits;

}  // namespace prism::oracle
