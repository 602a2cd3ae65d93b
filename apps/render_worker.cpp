#include "apps/render_worker.h"

#include <chrono>
#include <filesystem>
#include <new>
#include <optional>

#include "apps/frame_writer.h"

#include "core/image/image_output.h"
#include "core/render/render_engine.h"
#include "core/scene/scene_motion.h"

namespace prism::app {
namespace {

// `writer`: a sequence's frame writer (null for tiles, which go back to the coordinator).
WorkMessage render_item(const WorkerJob& job, RenderEngine& engine, LoadedScene& loaded, FrameWriter* writer,
                        int worker, int32_t item) {
    RenderSettings settings = job.settings;
    const Camera& camera = loaded.scene.camera;
    Camera frame_camera = camera;
    std::string frame_path;
    if (job.sequence) {
        uint32_t frame = job.frames.first + uint32_t(item);
        frame_camera = turntable_camera(camera_at(loaded.scene, frame / job.options.fps), frame,
                                        job.options.turntable_seconds, job.options.fps);
        if (scene_moves(loaded.scene))  // refits, not rebuilds: every worker's frame N is the same
            engine.move_to(loaded.scene, loaded.device, frame / job.options.fps);
        frame_path = numbered_output_path(job.out, frame);
    } else {
        settings.region = job.tiles[size_t(item)];
    }
    auto start = std::chrono::steady_clock::now();
    FrameResult frame = engine.render(frame_camera, settings);
    WorkMessage result;
    result.kind = MessageKind::Result;
    result.worker = worker;
    result.item = item;
    result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    result.rays_per_depth = frame.stats.rays_per_depth;
    result.shadow_rays_per_depth = frame.stats.shadow_rays_per_depth;
    if (job.sequence) {
        // Encoded while the next frame renders; the worker reports done only once every frame is on disk.
        writer->submit(
            {frame_path, job.format, frame.width, frame.height, std::move(frame.image), std::move(frame.radiance)});
    } else {
        result.image = std::move(frame.image);
        result.radiance = std::move(frame.radiance);
    }
    return result;
}

}  // namespace

void write_rendered_image(const std::string& path, ImageFormat format, uint32_t width, uint32_t height,
                          const std::vector<uint32_t>& image, const std::vector<float>& radiance) {
    write_image(path, format, int(width), int(height), image, radiance);
}

void run_worker(const WorkerJob& job, const std::string& backend, int worker,
                const std::function<WorkMessage(const WorkMessage&)>& exchange,
                const std::function<void(const WorkMessage&)>& notify) {
    std::string cause;
    try {
        LoadedScene loaded = load_and_build(job.scene, backend);
        if (job.sequence && scene_moves(loaded.scene) && loaded.device.bvh_options.flatten_instances) {
            // Spinning or animated instances move: the wide layout must keep its top level over them (BvhBuildOptions).
            SceneOptions moving = job.scene;
            moving.moving_instances = true;
            loaded.device = build_device_scene_for(loaded.scene, moving, loaded.device.bvh_options.layout);
        }
        RenderEngine engine(backend, loaded.device);
        WorkMessage hello;
        hello.kind = MessageKind::Hello;
        hello.worker = worker;
        hello.text = backend + "\n" + engine.info().device;
        WorkMessage answer = exchange(hello);
        std::optional<FrameWriter> writer;
        if (job.sequence) writer.emplace();
        FrameWriter* frames = writer ? &*writer : nullptr;
        while (answer.item >= 0) answer = exchange(render_item(job, engine, loaded, frames, worker, answer.item));
        if (writer) writer->finish();
        return;
    } catch (const std::bad_alloc&) {
        cause = "out of host memory";
    } catch (const std::exception& e) {
        cause = e.what();
    }
    WorkMessage failed;
    failed.kind = MessageKind::Failed;
    failed.worker = worker;
    failed.text = backend + "\n" + cause;
    notify(failed);
}

}  // namespace prism::app
