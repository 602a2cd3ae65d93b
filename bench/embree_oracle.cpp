#include "bench/embree_oracle.h"

#include <atomic>
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/util/error.h"
#include "core/util/thread_pool.h"

namespace prism::oracle {

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<uint32_t> instance_of_geometry;  // Embree geometry id → Prism instance index
    unsigned threads = 0;
};

EmbreeScene::EmbreeScene(const Scene& scene, unsigned threads) : impl_(std::make_unique<Impl>()) {
    impl_->threads = threads;
    std::string config = threads ? "threads=" + std::to_string(threads) : "";
    impl_->device = rtcNewDevice(config.c_str());
    if (!impl_->device) throw Error("embree: cannot create a device");
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes[instance.mesh];
        // Flattened into world space: Embree's own instancing would change the numbering, not the hits.
        RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            glm::vec3 p = glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f));
            vertices[3 * v] = p.x;
            vertices[3 * v + 1] = p.y;
            vertices[3 * v + 2] = p.z;
        }
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangles.size()));
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            indices[3 * t] = mesh.triangles[t].x;
            indices[3 * t + 1] = mesh.triangles[t].y;
            indices[3 * t + 2] = mesh.triangles[t].z;
        }
        rtcCommitGeometry(geometry);
        unsigned id = rtcAttachGeometry(impl_->scene, geometry);
        rtcReleaseGeometry(geometry);
        if (impl_->instance_of_geometry.size() <= id) impl_->instance_of_geometry.resize(id + 1);
        impl_->instance_of_geometry[id] = static_cast<uint32_t>(i);
    }
    rtcCommitScene(impl_->scene);
}

EmbreeScene::~EmbreeScene() {
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

namespace {

RayHit to_hit(float t, unsigned geometry, unsigned primitive, float u, float v, const std::vector<uint32_t>& map) {
    if (geometry == RTC_INVALID_GEOMETRY_ID)
        return RayHit{std::numeric_limits<float>::infinity(), 0xffffffffu, 0xffffffffu, 0.0f, 0.0f};
    return RayHit{t, map[geometry], primitive, u, v};
}

template <typename Work>
void parallel_chunks(unsigned threads, size_t count, size_t chunk, Work work) {
    std::atomic<size_t> next{0};
    ThreadPool pool(threads);
    pool.run([&](unsigned) {
        for (size_t first = next.fetch_add(chunk); first < count; first = next.fetch_add(chunk))
            work(first, std::min(first + chunk, count));
    });
}

}  // namespace

std::vector<RayHit> EmbreeScene::intersect1(const std::vector<RayQuery>& rays) const {
    std::vector<RayHit> out(rays.size());
    parallel_chunks(impl_->threads, rays.size(), 4096, [&](size_t first, size_t last) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = first; i < last; ++i) {
            const RayQuery& q = rays[i];
            RTCRayHit rh{};
            rh.ray.org_x = q.origin[0];
            rh.ray.org_y = q.origin[1];
            rh.ray.org_z = q.origin[2];
            rh.ray.tnear = q.tmin;
            rh.ray.dir_x = q.direction[0];
            rh.ray.dir_y = q.direction[1];
            rh.ray.dir_z = q.direction[2];
            rh.ray.tfar = q.tmax;
            rh.ray.mask = 0xffffffffu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(impl_->scene, &context, &rh);
            out[i] = to_hit(rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, impl_->instance_of_geometry);
        }
    });
    return out;
}

std::vector<RayHit> EmbreeScene::intersect8(const std::vector<RayQuery>& rays) const {
    std::vector<RayHit> out(rays.size());
    parallel_chunks(impl_->threads, rays.size(), 4096, [&](size_t first, size_t last) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t base = first; base < last; base += 8) {
            alignas(32) RTCRayHit8 rh{};
            alignas(32) int valid[8];
            for (int k = 0; k < 8; ++k) {
                size_t i = base + k;
                valid[k] = i < last ? -1 : 0;
                const RayQuery& q = rays[i < last ? i : first];
                rh.ray.org_x[k] = q.origin[0];
                rh.ray.org_y[k] = q.origin[1];
                rh.ray.org_z[k] = q.origin[2];
                rh.ray.tnear[k] = q.tmin;
                rh.ray.dir_x[k] = q.direction[0];
                rh.ray.dir_y[k] = q.direction[1];
                rh.ray.dir_z[k] = q.direction[2];
                rh.ray.tfar[k] = q.tmax;
                rh.ray.mask[k] = 0xffffffffu;
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect8(valid, impl_->scene, &context, &rh);
            for (int k = 0; k < 8 && base + k < last; ++k)
                out[base + k] = to_hit(rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.primID[k], rh.hit.u[k], rh.hit.v[k],
                                       impl_->instance_of_geometry);
        }
    });
    return out;
}

OracleRays make_oracle_rays(const Scene& scene, const EmbreeScene& embree, size_t primary, size_t total,
                            uint32_t seed) {
    OracleRays out;
    out.rays = bench::scene_camera_rays(scene, primary);
    out.primary = out.rays.size();
    std::vector<RayQuery> diffuse =
        bench::diffuse_rays(scene, out.rays, embree.intersect1(out.rays), total - std::min(total, primary), seed);
    out.rays.insert(out.rays.end(), diffuse.begin(), diffuse.end());
    out.diffuse = diffuse.size();
    return out;
}

}  // namespace prism::oracle
