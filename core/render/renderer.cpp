#include "core/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/util/error.h"

namespace prism {
namespace {

template <typename T>
void upload(Backend& backend, DeviceArray array, const UninitializedVector<T>& data) {
    backend.allocate(array, data.size() * sizeof(T));
    backend.write(array, data.data(), data.size() * sizeof(T));
}

float4 to_float4(glm::vec3 v, float w) { return float4{v.x, v.y, v.z, w}; }

// The top level holds exactly instance 0 (RT_FLAG_ONE_INSTANCE).
bool has_one_instance(const DeviceScene& scene) {
    return scene.instances.size() == 1 && scene.top_level.primitive_order.size() == 1;
}

// One instance in the stack layout: the one-mesh stages trace its rays (RT_FLAG_MESH_WALK).
bool takes_mesh_walk(const DeviceScene& scene) {
    return has_one_instance(scene) && scene.bvh_options.layout == BvhLayout::Stack;
}

}  // namespace

uint64_t FrameStats::total_rays() const {
    uint64_t total = 0;
    for (uint32_t n : rays_per_depth) total += n;
    for (uint32_t n : shadow_rays_per_depth) total += n;
    return total;
}

PixelRect render_region(const RenderSettings& settings) {
    if (settings.region.width == 0) return PixelRect{0, 0, settings.width, settings.height};
    return settings.region;
}

void check_render_settings(const RenderSettings& settings) {
    if (settings.width == 0 || settings.height == 0 || uint64_t(settings.width) * settings.height > (1u << 28))
        throw Error("image size " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                    " is out of range (1 to 2^28 pixels)");
    if (!(std::fabs(settings.exposure) <= 64.0f))  // NaN fails too
        throw Error("exposure " + std::to_string(settings.exposure) + " is out of range (-64 to 64 stops)");
    if (settings.max_depth < 1 || settings.max_depth > RT_MAX_DEPTH)
        throw Error("depth " + std::to_string(settings.max_depth) + " is out of range (1 to " +
                    std::to_string(RT_MAX_DEPTH) + ")");
    const PixelRect& r = settings.region;
    if (r.width != 0 && (r.height == 0 || r.x >= settings.width || r.y >= settings.height ||
                         r.width > settings.width - r.x || r.height > settings.height - r.y))
        throw Error("pixel region " + std::to_string(r.width) + "x" + std::to_string(r.height) + " at " +
                    std::to_string(r.x) + "," + std::to_string(r.y) + " is not inside the " +
                    std::to_string(settings.width) + "x" + std::to_string(settings.height) + " image");
}

FrameParams make_frame_params(const DeviceScene& scene, const Camera& camera, const RenderSettings& settings,
                              uint32_t queue_capacity, uint32_t shadow_capacity, uint32_t flags) {
    glm::vec3 forward = camera.target - camera.position;
    if (!(glm::length(forward) > 0.0f)) forward = glm::vec3(0, 0, -1);
    forward = glm::normalize(forward);
    glm::vec3 right = glm::cross(forward, camera.up);
    if (!(glm::length(right) > 1e-6f)) right = glm::cross(forward, glm::vec3(0, 0, 1));  // looking along up
    right = glm::normalize(right);
    glm::vec3 up = glm::cross(right, forward);
    float tan_half = std::tan(glm::radians(camera.vertical_fov_degrees) * 0.5f);
    float aspect = settings.height ? float(settings.width) / float(settings.height) : 1.0f;

    FrameParams p{};
    p.camera_position = to_float4(camera.position, 0.0f);
    p.camera_forward = to_float4(forward, 0.0f);
    p.camera_right = to_float4(right, 0.0f);
    p.camera_up = to_float4(up, 0.0f);
    p.environment = to_float4(scene.environment_tint, 0.0f);
    p.ambient_light = to_float4(scene.ambient_light, 0.0f);
    p.tan_half_fov = tan_half;
    p.aspect = aspect;
    p.environment_intensity = 1.0f;  // the tint carries it
    p.min_weight = settings.min_weight;
    p.width = settings.width;
    p.height = settings.height;
    p.max_depth = std::min(settings.max_depth, RT_MAX_DEPTH);
    p.light_count = scene.light_count;
    p.environment_kind = static_cast<uint32_t>(scene.environment_kind);
    p.environment_texture = scene.environment_texture;
    p.ray_capacity = queue_capacity;
    p.shadow_capacity = shadow_capacity;
    if (has_one_instance(scene)) flags |= RT_FLAG_ONE_INSTANCE;
    if (scene.bvh_options.flatten_instances) flags |= RT_FLAG_FLAT_INSTANCES;  // as built (build_device_scene)
    if (std::any_of(scene.materials.begin(), scene.materials.end(), [](const ::Material& m) {
            return (m.flags & (RT_MATERIAL_ALPHA_MASK | RT_MATERIAL_ALPHA_BLEND)) != 0u;
        }))
        flags |= RT_FLAG_ALPHA_SHADOWS;
    p.instance_count = static_cast<uint32_t>(scene.instances.size());
    p.bvh_layout = static_cast<uint32_t>(scene.bvh_options.layout);
    if (takes_mesh_walk(scene)) flags |= RT_FLAG_MESH_WALK;
    if (settings.tone_map == ToneMap::Neutral) flags |= RT_FLAG_TONE_MAP_NEUTRAL;
    p.flags = flags;
    p.exposure = std::exp2(settings.exposure);
    PixelRect region = render_region(settings);
    p.tile_x = region.x;
    p.tile_y = region.y;
    p.tile_width = region.width;
    p.tile_height = region.height;
    return p;
}

Renderer::Renderer(Backend& backend, const DeviceScene& scene) : backend_(backend), scene_(scene) {
    upload_scene();
    backend_.allocate(DeviceArray::counters, RT_COUNTER_SLOTS * sizeof(uint32_t));
    backend_.allocate(DeviceArray::frame, sizeof(FrameParams));
}

void Renderer::upload_scene() {
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    PRISM_IF_SCENE_ARRAY(role, upload(backend_, DeviceArray::name, scene_.name);)
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
}

void Renderer::update_instances(const DeviceScene& scene) {
    backend_.write(DeviceArray::instances, scene.instances.data(), scene.instances.size() * sizeof(::Instance));
    if (scene.bvh_options.layout == BvhLayout::Wide)
        backend_.write(DeviceArray::wide_nodes, scene.wide_nodes.data(), scene.top_level_nodes * sizeof(BvhWideNode));
    else
        backend_.write(DeviceArray::nodes, scene.nodes.data(), scene.top_level_nodes * sizeof(BvhNode));
}

void Renderer::update_mesh(const DeviceScene& scene, const DeviceScene::DeformableMesh& mesh) {
    // The entries [first, first + count) of one array, where the build put this mesh's.
    auto rewrite = [this](DeviceArray array, const auto& entries, size_t first, size_t count) {
        backend_.write(array, entries.data() + first, count * sizeof(entries[0]), first * sizeof(entries[0]));
    };
    rewrite(DeviceArray::vertices, scene.vertices, mesh.first_vertex, mesh.vertex_count);
    rewrite(DeviceArray::triangles, scene.triangles, mesh.first_triangle, mesh.bvh.primitive_order.size());
    if (scene.bvh_options.layout == BvhLayout::Wide) {
        rewrite(DeviceArray::wide_nodes, scene.wide_nodes, mesh.first_node, mesh.bvh.wide_nodes.size());
        rewrite(DeviceArray::triangle_blocks, scene.triangle_blocks, mesh.first_block, mesh.block_count);
    } else {
        rewrite(DeviceArray::nodes, scene.nodes, mesh.first_node, mesh.bvh.nodes.size());
    }
}

void Renderer::update_lights(const DeviceScene& scene) {
    backend_.write(DeviceArray::lights, scene.lights.data(), scene.lights.size() * sizeof(::Light));
}

void Renderer::enqueue_pass(StagePass pass, uint32_t depth, uint32_t frame_flags) {
    for (size_t s = 0; s < stage_count; ++s)
        if (stage_pass(Stage(s)) == pass && stage_runs(Stage(s), frame_flags)) backend_.enqueue(Stage(s), depth);
}

void Renderer::ensure_queues(uint32_t pixels, uint32_t ray_capacity, uint32_t shadow_capacity) {
    if (ray_capacity != ray_capacity_) {
        backend_.allocate(DeviceArray::rays, size_t(ray_capacity) * 2 * sizeof(Ray));
        backend_.allocate(DeviceArray::hits, size_t(ray_capacity) * sizeof(Hit));
        ray_capacity_ = ray_capacity;
    }
    if (shadow_capacity != shadow_capacity_) {
        backend_.allocate(DeviceArray::shadow_rays, size_t(std::max(shadow_capacity, 1u)) * sizeof(ShadowRay));
        shadow_capacity_ = shadow_capacity;
    }
    if (pixels != pixel_capacity_) {
        backend_.allocate(DeviceArray::accum, size_t(pixels) * RT_ACCUM_WORDS_PER_PIXEL * sizeof(uint32_t));
        backend_.allocate(DeviceArray::image, size_t(pixels) * sizeof(uint32_t));
        backend_.allocate(DeviceArray::radiance, size_t(pixels) * sizeof(float4));
        pixel_capacity_ = pixels;
    }
}

FrameResult Renderer::render(const Camera& camera, const RenderSettings& settings,
                             const std::function<void(uint32_t, uint32_t)>& progress) {
    check_render_settings(settings);
    const PixelRect region = render_region(settings);
    const uint32_t pixels = region.pixels();
    const uint32_t lights = std::max(scene_.light_count, 1u);
    float factor = std::max({settings.queue_factor, learned_queue_factor_, 1.0f});
    FrameResult result;
    result.width = region.width;
    result.height = region.height;

    for (uint32_t attempt = 0;; ++attempt) {
        uint32_t capacity = static_cast<uint32_t>(std::min<double>(double(pixels) * factor, 1u << 30));
        capacity = std::max(capacity, pixels);
        uint32_t shadow_capacity = static_cast<uint32_t>(std::min<double>(double(capacity) * lights, 1u << 30));
        ensure_queues(pixels, capacity, shadow_capacity);

        auto start = std::chrono::steady_clock::now();
        FrameParams params = make_frame_params(scene_, camera, settings, capacity, shadow_capacity, 0);
        std::vector<uint32_t> counters(RT_COUNTER_SLOTS, 0u);
        counters[RT_COUNTER_RAYS] = pixels;
        backend_.write(DeviceArray::frame, &params, sizeof params);
        backend_.write(DeviceArray::counters, counters.data(), counters.size() * sizeof(uint32_t));
        backend_.zero(DeviceArray::accum);

        // Every depth is enqueued up front: the queues' counts stay on the device, so the frame needs no host
        // round trip (the seed copied hits back at each depth).
        enqueue_pass(StagePass::Before, 0, params.flags);
        for (uint32_t depth = 0; depth < params.max_depth; ++depth) {
            enqueue_pass(StagePass::Bounce, depth, params.flags);
            if (progress) progress(depth + 1, params.max_depth);
        }
        enqueue_pass(StagePass::After, 0, params.flags);
        if (settings.copy_to_gl) {
            GlInteropOffer offer = backend_.gl_interop();
            if (!offer.interop) throw Error("render: copy_to_gl without a GL interop (" + offer.reason + ")");
            offer.interop->copy_image(size_t(pixels) * sizeof(uint32_t));
        }
        auto enqueued = std::chrono::steady_clock::now();
        backend_.read(DeviceArray::counters, counters.data(), counters.size() * sizeof(uint32_t));
        auto counted = std::chrono::steady_clock::now();
        // The frame lands in host memory the backend keeps page-locked (or mapped) from frame to frame, as a
        // real-time caller would read it; the copy into the result's vectors is after the clock. Page-locked memory
        // can run out where pageable memory does not (the radiance of a 16K frame is 4 GiB): then the array is read
        // into the result's own (pageable) memory with read(), inside the clock.
        auto read_back = [&](DeviceArray array, auto& into, size_t bytes) -> const void* {
            if (bytes == 0) return nullptr;
            try {
                return backend_.read_pinned(array, bytes);
            } catch (const Error&) {
                into.resize(bytes / sizeof(into[0]));
                backend_.read(array, into.data(), bytes);  // a device fault throws here again, with its cause
                return into.data();
            }
        };
        const size_t image_bytes = settings.read_image ? size_t(pixels) * sizeof(uint32_t) : 0u;
        const size_t radiance_bytes = settings.read_radiance ? size_t(pixels) * 4 * sizeof(float) : 0u;
        const void* image = read_back(DeviceArray::image, result.image, image_bytes);
        const void* radiance = read_back(DeviceArray::radiance, result.radiance, radiance_bytes);
        result.stats.stages = backend_.finish();
        auto end = std::chrono::steady_clock::now();
        result.image.resize(image_bytes / sizeof(uint32_t));
        if (image && image != result.image.data()) std::memcpy(result.image.data(), image, image_bytes);
        result.radiance.resize(radiance_bytes / sizeof(float));
        if (radiance && radiance != result.radiance.data())
            std::memcpy(result.radiance.data(), radiance, radiance_bytes);
        using ms = std::chrono::duration<double, std::milli>;
        result.stats.frame_ms = ms(end - start).count();
        result.stats.enqueue_ms = ms(enqueued - start).count();
        result.stats.device_wait_ms = ms(counted - enqueued).count();
        result.stats.readback_ms = ms(end - counted).count();

        if (counters[RT_COUNTER_DROPPED] == 0 || capacity >= (1u << 30) || attempt >= 4) {
            result.stats.queue_capacity = capacity;
            result.stats.regrows = attempt;
            result.stats.rays_per_depth.clear();
            result.stats.shadow_rays_per_depth.clear();
            for (uint32_t d = 0; d < params.max_depth; ++d) {
                result.stats.rays_per_depth.push_back(std::min(counters[RT_COUNTER_RAYS + d], capacity));
                result.stats.shadow_rays_per_depth.push_back(
                    std::min(counters[RT_COUNTER_SHADOWS + d], shadow_capacity));
            }
            if (counters[RT_COUNTER_DROPPED] != 0)
                throw Error("frame needs more than the largest ray queue (" + std::to_string(capacity) +
                            " rays); lower --depth or the resolution");
            return result;
        }
        // A queue overflowed: the image would be missing rays. Grow to what the counters say was needed.
        uint32_t needed = 0;
        for (uint32_t d = 0; d <= params.max_depth && d < RT_MAX_DEPTH + 1; ++d)
            needed = std::max(needed, counters[RT_COUNTER_RAYS + d]);
        factor = std::max(factor * 2.0f, float(needed) / float(pixels) * 1.25f);
        learned_queue_factor_ = factor;
    }
}

Stage Renderer::query_stage(bool any_hit) const {
    if (takes_mesh_walk(scene_)) return any_hit ? Stage::OccludeMesh : Stage::IntersectMesh;
    return any_hit ? Stage::Occlude : Stage::Intersect;
}

std::vector<RayHit> Renderer::trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches) {
    launches = std::max(launches, 1u);
    const Stage stage = query_stage(any_hit);
    std::vector<RayHit> out(rays.size());
    const uint32_t batch = 1u << 22;  // 4M rays: 256 MiB of rays + 128 MiB of hits
    RenderSettings settings;
    settings.width = 1;
    settings.height = 1;
    settings.max_depth = 1;
    last_launch_ms_.assign(launches, 0.0);
    for (size_t first = 0; first < rays.size(); first += batch) {
        uint32_t n = static_cast<uint32_t>(std::min<size_t>(batch, rays.size() - first));
        uint32_t capacity = std::max(n, ray_capacity_);
        ensure_queues(std::max(pixel_capacity_, 1u), capacity, std::max(shadow_capacity_, 1u));
        FrameParams params = make_frame_params(scene_, Camera{}, settings, ray_capacity_, shadow_capacity_,
                                               RT_FLAG_NO_SHADING | (any_hit ? RT_FLAG_ANY_HIT : 0u));
        std::vector<Ray> device_rays(n);
        for (uint32_t i = 0; i < n; ++i) {
            const RayQuery& q = rays[first + i];
            device_rays[i] = Ray{float4{q.origin[0], q.origin[1], q.origin[2], q.tmin},
                                 float4{q.direction[0], q.direction[1], q.direction[2], q.tmax},
                                 float4{0, 0, 0, 0},
                                 i,
                                 RT_CHANNEL_ALL,
                                 0,
                                 0};
        }
        std::vector<uint32_t> counters(RT_COUNTER_SLOTS, 0u);
        counters[RT_COUNTER_RAYS] = n;
        backend_.write(DeviceArray::frame, &params, sizeof params);
        backend_.write(DeviceArray::rays, device_rays.data(), device_rays.size() * sizeof(Ray));
        for (uint32_t launch = 0; launch < launches; ++launch) {
            // Each launch takes its rays from the counters afresh (RT_WORK_LOOP's taken count starts at zero).
            backend_.write(DeviceArray::counters, counters.data(), counters.size() * sizeof(uint32_t));
            backend_.enqueue(stage, 0);
        }
        std::vector<Hit> hits(n);
        backend_.read(DeviceArray::hits, hits.data(), hits.size() * sizeof(Hit));
        std::vector<StageTiming> timings = backend_.finish();
        for (size_t launch = 0; launch < std::min<size_t>(timings.size(), launches); ++launch)
            last_launch_ms_[launch] += timings[launch].milliseconds;
        for (uint32_t i = 0; i < n; ++i) {
            const Hit& h = hits[i];
            out[first + i] = RayHit{h.tuv.x, h.instance, h.primitive, h.tuv.y, h.tuv.z};
        }
    }
    return out;
}

}  // namespace prism
