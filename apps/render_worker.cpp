#include "apps/render_worker.h"

#include <cctype>
#include <chrono>
#include <filesystem>
#include <new>

#include "core/image_io.h"
#include "core/render_engine.h"

namespace prism::app {
namespace {

WorkMessage render_item(const WorkerJob& job, RenderEngine& engine, const Camera& camera, int worker, int32_t item) {
    RenderSettings settings = job.settings;
    Camera frame_camera = camera;
    std::string frame_path;
    if (job.sequence) {
        uint32_t frame = job.frames.first + uint32_t(item);
        frame_camera = turntable_camera(camera, frame, job.options.turntable_seconds, job.options.fps);
        frame_path = numbered_output_path(job.out, frame);
        settings.read_radiance = wants_radiance(frame_path);
    } else {
        settings.region = job.tiles[size_t(item)];
        settings.read_radiance = wants_radiance(job.out);
    }
    auto start = std::chrono::steady_clock::now();
    FrameResult frame = engine.render(frame_camera, settings);
    if (job.sequence) write_rendered_image(frame_path, frame.width, frame.height, frame.image, frame.radiance);
    WorkMessage result;
    result.kind = MessageKind::Result;
    result.worker = worker;
    result.item = item;
    result.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    result.rays_per_depth = frame.stats.rays_per_depth;
    result.shadow_rays_per_depth = frame.stats.shadow_rays_per_depth;
    if (!job.sequence) {
        result.image = std::move(frame.image);
        result.radiance = std::move(frame.radiance);
    }
    return result;
}

}  // namespace

bool wants_radiance(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".hdr";
}

void write_rendered_image(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint32_t>& image,
                          const std::vector<float>& radiance) {
    if (wants_radiance(path)) write_hdr(path, int(width), int(height), radiance);
    else write_png(path, int(width), int(height), image);
}

void run_worker(const WorkerJob& job, const std::string& backend, int worker,
                const std::function<WorkMessage(const WorkMessage&)>& exchange,
                const std::function<void(const WorkMessage&)>& notify) {
    std::string cause;
    try {
        LoadedScene loaded = load_and_build(job.scene, backend);
        RenderEngine engine(backend, loaded.device);
        WorkMessage hello;
        hello.kind = MessageKind::Hello;
        hello.worker = worker;
        hello.text = backend + "\n" + engine.info().device;
        WorkMessage answer = exchange(hello);
        while (answer.item >= 0) answer = exchange(render_item(job, engine, loaded.scene.camera, worker, answer.item));
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
