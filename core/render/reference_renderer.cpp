#include "core/render/reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>

#include "core/util/error.h"
#include "core/render/host_globals.h"
#include "core/render/host_memory.h"
#include "core/util/thread_pool.h"
#include "kernels/stages.h"

namespace prism {
namespace {

struct RayCounts {
    std::vector<uint64_t> per_depth = std::vector<uint64_t>(RT_MAX_DEPTH + 1, 0);
    std::vector<uint64_t> shadows_per_depth = std::vector<uint64_t>(RT_MAX_DEPTH + 1, 0);
};

// Thesis 6.3.6: intersect; no hit → background; else the local colour, shadow rays, then the reflected and
// refracted rays recursively. The children carry their weights (eqs. 6.31/6.32), so each contribution is
// added to the pixel directly: the same sum as eq. 6.7 evaluated bottom-up.
void trace_recursive(KernelGlobals kg, const Ray& ray, RayCounts& counts) {
    FrameParams frame = kg.frame[0];
    uint32_t depth = ray.depth;
    counts.per_depth[depth]++;
    Hit hit = rt_trace(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), ray.origin.w, ray.direction.w, false);
    if (!(hit.tuv.x < RT_INFINITY)) {
        rt_accumulate(kg, ray.pixel, rt_xyz(ray.weight) * rt_environment(kg, rt_xyz(ray.direction)));
        return;
    }
    Ray children[RT_MAX_CHILDREN];
    ShadeResult shade = rt_shade(kg, ray, hit, children);
    rt_accumulate(kg, ray.pixel, rt_xyz(shade.emitted));
    for (uint32_t l = 0; l < frame.light_count; ++l) {
        ShadowRay sr = rt_shadow_ray(kg, shade.lit, l, ray.pixel);
        if (sr.contribution.w == 0.0f) continue;
        counts.shadows_per_depth[depth]++;
        float3 reaching = rt_light_reaching(kg, sr);
        if (rt_max3(reaching) > 0.0f) rt_accumulate(kg, sr.pixel, reaching);
    }
    for (uint32_t c = 0; c < shade.child_count; ++c) trace_recursive(kg, children[c], counts);
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(const DeviceScene& scene, unsigned threads) : scene_(scene), threads_(threads) {}

FrameResult ReferenceRenderer::render(const Camera& camera, const RenderSettings& settings,
                                      const std::function<void(double)>& progress) {
    check_render_settings(settings);
    check_host_memory(
        frame_host_bytes(settings, FrameArrays::HostReference),
        "a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) + " frame on cpu-ref");
    auto start = std::chrono::steady_clock::now();
    const PixelRect region = render_region(settings);
    const uint32_t pixels = region.pixels();
    FrameParams frame = make_frame_params(scene_, camera, settings, 0, 0, 0);
    std::vector<uint32_t> accum(size_t(pixels) * RT_ACCUM_WORDS_PER_PIXEL, 0u);
    FrameResult result;
    result.width = region.width;
    result.height = region.height;
    result.image.resize(pixels);
    std::vector<float4> radiance(pixels);
    KernelGlobals kg = host_globals(scene_, &frame, accum.data(), result.image.data(), radiance.data());

    // Tiles of 16x16 pixels handed out dynamically: cost varies a lot between glass and background.
    const uint32_t tile = 16;
    const uint32_t tiles_x = (region.width + tile - 1) / tile;
    const uint32_t tiles = tiles_x * ((region.height + tile - 1) / tile);
    std::atomic<uint32_t> next{0};
    std::atomic<uint32_t> finished{0};
    ThreadPool pool(threads_);
    std::vector<RayCounts> counts(pool.size());
    pool.run([&](unsigned worker) {
        for (uint32_t t = next++; t < tiles; t = next++) {
            uint32_t x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
            for (uint32_t y = y0; y < std::min(y0 + tile, region.height); ++y)
                for (uint32_t x = x0; x < std::min(x0 + tile, region.width); ++x)
                    trace_recursive(kg, rt_primary_ray(frame, y * region.width + x), counts[worker]);
            uint32_t done = ++finished;
            if (progress && worker == 0) progress(double(done) / tiles);
        }
    });
    for (uint32_t i = 0; i < pixels; ++i) rt_stage_resolve(kg, i);
    if (settings.read_radiance) {
        result.radiance.resize(size_t(pixels) * 4);
        for (uint32_t i = 0; i < pixels; ++i) {
            result.radiance[4 * i + 0] = radiance[i].x;
            result.radiance[4 * i + 1] = radiance[i].y;
            result.radiance[4 * i + 2] = radiance[i].z;
            result.radiance[4 * i + 3] = radiance[i].w;
        }
    }
    for (uint32_t d = 0; d < frame.max_depth; ++d) {
        uint64_t rays = 0, shadows = 0;
        for (const RayCounts& c : counts) {
            rays += c.per_depth[d];
            shadows += c.shadows_per_depth[d];
        }
        result.stats.rays_per_depth.push_back(static_cast<uint32_t>(rays));
        result.stats.shadow_rays_per_depth.push_back(static_cast<uint32_t>(shadows));
    }
    result.stats.frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::vector<RayHit> ReferenceRenderer::trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches) {
    RenderSettings settings;
    FrameParams frame = make_frame_params(scene_, Camera{}, settings, 0, 0, 0);
    KernelGlobals kg = host_globals(scene_, &frame, nullptr, nullptr, nullptr);
    std::vector<RayHit> out(rays.size());
    ThreadPool pool(threads_);
    last_launch_ms_.clear();
    for (uint32_t launch = 0; launch < std::max(launches, 1u); ++launch) {
        std::atomic<size_t> next{0};
        auto start = std::chrono::steady_clock::now();
        pool.run([&](unsigned) {
            const size_t chunk = 4096;
            for (size_t first = next.fetch_add(chunk); first < rays.size(); first = next.fetch_add(chunk)) {
                for (size_t i = first; i < std::min(first + chunk, rays.size()); ++i) {
                    const RayQuery& q = rays[i];
                    Hit h = rt_trace(kg, float3{q.origin[0], q.origin[1], q.origin[2]},
                                     float3{q.direction[0], q.direction[1], q.direction[2]}, q.tmin, q.tmax, any_hit);
                    out[i] = RayHit{h.tuv.x, h.instance, h.primitive, h.tuv.y, h.tuv.z};
                }
            }
        });
        last_launch_ms_.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    return out;
}

}  // namespace prism
