// `prism render`: one frame of a scene on one backend, written as PNG (8-bit sRGB) or .hdr (linear float).
#include <chrono>
#include <cstdio>
#include <unistd.h>

#include "apps/commands.h"
#include "apps/frame_report.h"
#include "apps/render_distributed.h"
#include "apps/scene_options.h"
#include "core/build_info.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/output_file.h"
#include "core/render_engine.h"

namespace prism::app {
namespace {

struct RenderOptions {
    SceneOptions scene;
    std::string backend = "auto";
    RenderSettings settings;
    std::string out;
    std::string stats;
    DistributedOptions distributed;
};

void print_progress(double fraction) {
    int filled = static_cast<int>(fraction * 30.0 + 0.5);
    std::fprintf(stderr, "\r  [%.*s%*s] %3d%%", filled, "##############################", 30 - filled, "",
                 static_cast<int>(fraction * 100.0 + 0.5));
    std::fflush(stderr);
}

void run_render(const RenderOptions& options) {
    if (wants_distributed_render(options.backend, options.distributed))
        return run_distributed_render({options.scene, options.backend, options.settings, options.out, options.stats,
                                       options.distributed});
    check_output_extension(options.out);   // fail before any work
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
                loaded.device.bvh_build_ms, options.scene.bvh.c_str(), loaded.layout.c_str(),
                loaded.device.sah_cost, upload_ms);
    std::fflush(stdout);

    std::string extension = std::filesystem::path(options.out).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    RenderSettings settings = options.settings;
    settings.read_radiance = extension == ".hdr";
    bool terminal = isatty(STDERR_FILENO);
    FrameResult frame = engine.render(loaded.scene.camera, settings,
                                      terminal ? std::function<void(double)>(print_progress) : nullptr);
    if (terminal) std::fprintf(stderr, "\r%*s\r", 44, "");
    std::printf("%s", frame_summary(frame, options.settings).c_str());

    if (extension == ".hdr") write_hdr(options.out, int(frame.width), int(frame.height), frame.radiance);
    else write_png(options.out, int(frame.width), int(frame.height), frame.image);
    if (!options.stats.empty()) {
        nlohmann::json stats = frame_json(frame, options.settings, info);
        stats["scene"] = options.scene.scene;
        stats["commit"] = build_commit();
        stats["bvh"] = {{"method", options.scene.bvh}, {"layout", loaded.layout},
                        {"build_ms", loaded.device.bvh_build_ms}, {"sah_cost", loaded.device.sah_cost}};
        write_file_atomically(options.stats, stats.dump(2) + "\n");
    }
    std::printf("  wrote %s (total %.0f ms)\n", options.out.c_str(),
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto options = std::make_shared<RenderOptions>();
    auto* command = app.add_subcommand("render", "Render one frame to a PNG (8-bit sRGB) or .hdr (linear float)");
    add_scene_options(command, options->scene);
    command->add_option("--backend", options->backend,
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
    command->add_option("--out", options->out, "output image: .png or .hdr")->required();
    command->add_option("--stats", options->stats, "write frame statistics as JSON");
    add_distributed_options(command, options->distributed);
    command->callback([options] { run_render(*options); });
}

}  // namespace prism::app
