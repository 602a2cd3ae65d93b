// The wavefront frame (architecture.md): the order of stages, queue sizing and read-back, driven through the
// Backend interface so every API runs exactly the same schedule.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/render/backend.h"
#include "core/render/device_scene.h"

namespace prism {

// A rectangle of pixels, x and y of its top-left corner (row 0 at the top).
struct PixelRect {
    uint32_t x = 0, y = 0, width = 0, height = 0;
    uint32_t pixels() const { return width * height; }
};

// How the frame's light becomes the image (kernels/display.h): none clips at 1, as the seed did.
enum class ToneMap : uint32_t { None = 0, Neutral = 1 };

struct RenderSettings {
    uint32_t width = 1280;
    uint32_t height = 720;
    uint32_t max_depth = 8;     // ray generations traced: 1 = primary rays only
    float min_weight = 1e-4f;   // rays whose RGB weight is below this everywhere are not spawned
    float queue_factor = 2.0f;  // ray queue capacity per pixel; grown automatically when a frame overflows
    // The light is scaled by 2^exposure (photographic stops) for every output, then tone-mapped for the image.
    float exposure = 0.0f;
    ToneMap tone_map = ToneMap::None;
    // What render() copies back into FrameResult. The viewer needs only the image for its host copy, and nothing
    // when the display copies the device's image array itself (GL interop). The linear radiance (16 bytes a pixel:
    // 33 MB at 1080p) only .hdr output and the bit-exactness tests need, so frames and benchmarks skip it.
    bool read_image = true;
    bool read_radiance = false;
    // The viewer's interop display: right after resolve the frame's `image` array is copied on the device into the
    // buffer the backend shares with GL (GlInterop::copy_image, core/render/gl_interop.h), in the frame's own
    // submission, so render() returning means GL may draw it. Needs a backend that offers GL interop.
    bool copy_to_gl = false;
    // Only these pixels of the width x height image are rendered (a tile of a frame split over devices or MPI
    // ranks: core/render/tiles.h); empty (width 0) means the whole image. The rendered pixels are bit-identical to the
    // same pixels of the whole image, and FrameResult then holds the region only.
    PixelRect region;
};

// settings.region, or the whole image when it is empty.
PixelRect render_region(const RenderSettings& settings);

struct FrameStats {
    double frame_ms = 0.0;  // wall time of the whole frame, upload of parameters to read-back
    // Where the host's frame time went: recording/launching every stage, waiting for the device to finish them
    // (the first read-back waits), then reading the image back. Device time per stage is in `stages`.
    double enqueue_ms = 0.0, device_wait_ms = 0.0, readback_ms = 0.0;
    std::vector<StageTiming> stages;       // per stage and depth (device timers where the API has them)
    std::vector<uint32_t> rays_per_depth;  // closest-hit rays traced at each depth
    std::vector<uint32_t> shadow_rays_per_depth;
    uint32_t queue_capacity = 0;
    uint32_t regrows = 0;  // frames re-run with larger queues because one overflowed
    uint64_t total_rays() const;
};

struct FrameResult {
    uint32_t width = 0, height = 0;  // of the rendered region (the whole image unless settings.region is set)
    std::vector<uint32_t> image;     // RGBA8 sRGB, row 0 at the top (empty when settings.read_image was false)
    std::vector<float> radiance;     // linear RGBA (empty unless settings.read_radiance)
    FrameStats stats;
};

// Throws prism::Error for an image size, depth or region the frame cannot have (shared by every renderer).
void check_render_settings(const RenderSettings& settings);

// The camera basis and frame constants the kernels read.
FrameParams make_frame_params(const DeviceScene& scene, const Camera& camera, const RenderSettings& settings,
                              uint32_t queue_capacity, uint32_t shadow_capacity, uint32_t flags);

// One-line hit record of a ray query (the `prism rays` output, docs/ray-queries.md).
struct RayHit {
    float t;  // +inf on a miss
    uint32_t instance;
    uint32_t primitive;
    float u, v;
};
struct RayQuery {
    float origin[3];
    float tmin;
    float direction[3];
    float tmax;
};

class Renderer {
public:
    Renderer(Backend& backend, const DeviceScene& scene);
    FrameResult render(const Camera& camera, const RenderSettings& settings,
                       const std::function<void(uint32_t depth, uint32_t max_depth)>& progress = {});
    // Closest (or any) hit of each ray: the intersect stage alone, in batches that fit the device. Each batch's
    // rays are uploaded once and traced `launches` times back to back (every launch finds the same hits), so that
    // a benchmark can time launches whose tree is already in the device's caches, as tinybvh's does.
    std::vector<RayHit> trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches = 1);
    // The stage trace() launches: occlude for any hit, intersect for the closest, or their one-mesh variants
    // (occlude_mesh, intersect_mesh) for a scene of one instance in the stack layout.
    Stage query_stage(bool any_hit) const;
    // Device time of that stage in each launch of the last trace() (all batches), for throughput measurements.
    const std::vector<double>& last_launch_ms() const { return last_launch_ms_; }
    // After update_instance_transforms: re-uploads the instances and the top-level nodes only.
    void update_instances(const DeviceScene& scene);
    // After update_mesh_vertices: re-uploads what the posed mesh changed (its vertices, triangles, triangle blocks
    // and BVH nodes); update_instances then uploads the top level.
    void update_mesh(const DeviceScene& scene, const DeviceScene::DeformableMesh& mesh);
    // After update_lights: re-uploads the lights.
    void update_lights(const DeviceScene& scene);

private:
    void upload_scene();
    void ensure_queues(uint32_t pixels, uint32_t rays_capacity, uint32_t shadow_capacity);
    // Every stage of kernels/stage_list.h in `pass` that a frame with these RT_FLAG_* bits runs, in list order, at
    // `depth`.
    void enqueue_pass(StagePass pass, uint32_t depth, uint32_t frame_flags);

    Backend& backend_;
    const DeviceScene& scene_;
    uint32_t ray_capacity_ = 0;
    uint32_t shadow_capacity_ = 0;
    uint32_t pixel_capacity_ = 0;
    std::vector<double> last_launch_ms_;
    float learned_queue_factor_ = 0.0f;  // what an overflowing frame needed: later frames start there
};

}  // namespace prism
