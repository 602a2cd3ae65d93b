// `prism render`: one frame of a scene on one backend, written as PNG (8- or 16-bit sRGB), OpenEXR or .hdr (the
// linear radiance, unclamped).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <optional>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/display_options.h"
#include "apps/frame_report.h"
#include "apps/mpi_session.h"
#include "apps/option_checks.h"
#include "apps/progress.h"
#include "apps/render_distributed.h"
#include "apps/scene_options.h"
#include "core/util/build_info.h"
#include "core/util/error.h"
#include "core/image/image_output.h"
#include "core/util/output_file.h"
#include "core/render/render_engine.h"

namespace prism::app {
namespace {

struct RenderOptions {
    SceneOptions scene;
    std::string backend = "auto";
    RenderSettings settings;
    std::string out;
    int png_depth = 8;
    std::string stats;
    DistributedOptions distributed;
};

void run_render(const RenderOptions& options) {
    route_output();
    RenderSettings settings = options.settings;
    ImageFormat format = ImageFormat::Png8;
    try {  // every check before any work
        format = output_image_format(options.out, options.png_depth);
        settings.read_radiance = needs_linear_radiance(format);
        check_render_options(options.backend, settings, options.out, options.stats);
    } catch (const Error&) {
        if (started_as_mpi_rank() && launcher_rank() > 0) std::exit(1);  // rank 0 says it, once
        throw;
    }
    if (wants_distributed_render(options.backend, options.distributed))
        return run_distributed_render(
            {options.scene, options.backend, settings, options.out, format, options.stats, options.distributed});
    auto start = std::chrono::steady_clock::now();
    LoadedScene loaded = load_and_build(options.scene, options.backend);
    auto built = std::chrono::steady_clock::now();
    RenderEngine engine(options.backend, loaded.device);
    BackendInfo info = engine.info();
    double upload_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - built).count();
    std::printf("prism render: %s (%zu triangles, %zu instances) on %s [%s]\n", options.scene.scene.c_str(),
                loaded.device.traced_triangles, loaded.device.instances.size(), info.name.c_str(), info.device.c_str());
    for (const std::string& warning : loaded.scene.warnings) std::printf("  warning: %s\n", warning.c_str());
    std::printf("  load %.1f ms, BVH %.1f ms (%s, %s layout, SAH cost %.1f), upload %.1f ms\n", loaded.load_ms,
                loaded.device.bvh_build_ms, options.scene.bvh.c_str(), loaded.layout.c_str(), loaded.device.sah_cost,
                upload_ms);
    std::fflush(stdout);

    Progress rendering("rendering " + std::to_string(settings.width) + "x" + std::to_string(settings.height));
    bool by_depth = info.name != "cpu-ref";  // the wavefront backends report each depth; cpu-ref its tiles
    FrameResult frame;
    try {
        frame = engine.render(loaded.scene.camera, settings, [&](double fraction) {
            uint32_t depths_done = uint32_t(fraction * settings.max_depth + 1e-6);
            rendering.update(
                fraction,
                by_depth ? "depth " + std::to_string(depths_done) + "/" + std::to_string(settings.max_depth) : "tiles");
        });
    } catch (const std::bad_alloc&) {
        throw Error(options.scene.scene + ": out of host memory while rendering on " + info.name);
    }
    rendering.finish();
    std::printf("%s", frame_summary(frame, options.settings).c_str());

    // The stats wait under a temporary name until the image is written: both appear, or neither.
    std::optional<StagedOutput> stats_file;
    if (!options.stats.empty()) {
        nlohmann::json stats = frame_json(frame, options.settings, info);
        stats["scene"] = options.scene.scene;
        stats["commit"] = build_commit();
        stats["bvh"] = {{"method", options.scene.bvh},
                        {"layout", loaded.layout},
                        {"leaf_size", options.scene.bvh_leaf_size},
                        {"node_cost", options.scene.bvh_node_cost},
                        {"build_ms", loaded.device.bvh_build_ms},
                        {"closed_solid_instances", loaded.device.closed_solid_instances},
                        {"closed_solid_ms", loaded.device.closed_solid_ms},
                        {"sah_cost", loaded.device.sah_cost}};
        stats_file.emplace(options.stats, stats.dump(2) + "\n");
    }
    write_image(options.out, format, int(frame.width), int(frame.height), frame.image, frame.radiance);
    if (stats_file) {
        try {
            stats_file->commit();
        } catch (const Error&) {
            std::error_code ignored;
            std::filesystem::remove(options.out, ignored);
            throw;
        }
    }
    std::printf("  wrote %s (total %.0f ms)\n", options.out.c_str(),
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto options = std::make_shared<RenderOptions>();
    auto* command = app.add_subcommand(
        "render", "Render one frame to a PNG (8- or 16-bit sRGB), OpenEXR or .hdr (both linear and unclamped)");
    add_scene_options(command, options->scene);
    command
        ->add_option("--backend", options->backend,
                     "auto, cpu-ref, cpu, cuda, opencl, vulkan; a device after a colon (opencl:pocl, vulkan:nvidia), "
                     "every device with :all (cuda:all); a comma list splits the frame over several (one entry "
                     "per MPI rank under mpirun)")
        ->capture_default_str();
    command->add_option("--width", options->settings.width, "image width")->capture_default_str();
    command->add_option("--height", options->settings.height, "image height")->capture_default_str();
    command->add_option("--depth", options->settings.max_depth, "ray generations traced (1 = primary rays only)")
        ->capture_default_str();
    command->add_option("--min-weight", options->settings.min_weight, "smallest ray weight still traced")
        ->capture_default_str();
    add_display_options(command, options->settings);
    add_output_option(command, options->out, "output image: .png (sRGB), .exr (half float) or .hdr (RGBE)")->required();
    command->add_option("--png-depth", options->png_depth, "bits per channel of .png output: 8 or 16")
        ->check(CLI::IsMember({8, 16}))
        ->capture_default_str();
    command->add_option("--stats", options->stats, "write frame statistics as JSON");
    add_distributed_options(command, options->distributed);
    command->callback([options] { run_render(*options); });
}

}  // namespace prism::app
