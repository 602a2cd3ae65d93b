// Embree's BVH builds beside Prism's (bench/bvh_build_bench.cpp): how long rtcCommitScene takes for a triangle
// mesh (the BVH Embree traces), and the binary tree Embree's own SAH builder (rtcBuildBVH) makes over the same
// primitive bounds, written as a Prism BVH so that Prism's sah_cost() measures both trees the same way.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/bvh/bvh.h"
#include "core/util/non_copyable.h"

namespace prism::oracle {

enum class EmbreeQuality { Low, Medium, High };  // RTC_BUILD_QUALITY_*
const char* embree_quality_name(EmbreeQuality quality);
const char* embree_version();  // of the headers built against

struct TriangleSoupView {
    std::span<const glm::vec3> positions;
    std::span<const glm::uvec3> triangles;
};

// One device with `threads` threads (0: all) for all the builds below.
class EmbreeBuilder : private NonCopyable {
public:
    explicit EmbreeBuilder(unsigned threads);
    ~EmbreeBuilder();

    // Milliseconds spent in rtcCommitScene for a new scene holding the mesh as one triangle geometry (buffers
    // shared, not copied; making the scene and geometry is not timed).
    double commit_ms(const TriangleSoupView& mesh, EmbreeQuality quality) const;

    // rtcBuildBVH with branching factor 2 over the usable bounds (those Prism's builder keeps), leaves of at most
    // max_leaf_size primitives, SAH costs 1/1 and leaf cost counted in blocks of sah_block_size primitives. The
    // result is in Prism's stack layout (nodes, primitive_order, depth); build_ms is the rtcBuildBVH call alone.
    Bvh build_binary(std::span<const Aabb> bounds, EmbreeQuality quality, uint32_t max_leaf_size,
                     uint32_t sah_block_size) const;

private:
    void* device_;  // RTCDevice
};

}  // namespace prism::oracle
