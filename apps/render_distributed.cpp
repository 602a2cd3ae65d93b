#include "apps/render_distributed.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <thread>

#include "apps/frame_report.h"
#include "apps/mpi_session.h"
#include "apps/render_worker.h"
#include "apps/work_coordinator.h"
#include "apps/worker_plan.h"
#include "core/util/build_info.h"
#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/util/output_file.h"
#include "core/render/render_engine.h"
#include "core/render/tiles.h"

namespace prism::app {
namespace {

using Clock = std::chrono::steady_clock;

WorkerJob make_job(const DistributedRender& render) {
    WorkerJob job;
    job.scene = render.scene;
    job.scene.layout = bvh_layout_name(shared_bvh_layout(render.scene.layout, render.backend));
    job.settings = render.settings;
    job.settings.read_image = true;
    job.out = render.out;
    job.format = render.format;
    job.options = render.options;
    job.sequence = !render.options.frames.empty();
    if (!job.sequence && render.options.turntable_seconds > 0.0)
        throw Error("--turntable needs --frames (a sequence of frames to turn over)");
    check_render_settings(render.settings);
    if (job.sequence) {
        job.frames = parse_frame_range(render.options.frames);
        check_numbered_output_pattern(render.out);
    } else {
        job.tiles = split_into_tiles(render.settings.width, render.settings.height, render.options.tile_size);
    }
    return job;
}

// The workers of this process, each in its own thread; `exchange`/`notify` reach the coordinator.
void run_local_workers(const WorkerJob& job, const std::vector<std::string>& backends,
                       const std::function<WorkMessage(const WorkMessage&)>& exchange,
                       const std::function<void(const WorkMessage&)>& notify) {
    std::vector<std::thread> threads;
    for (size_t w = 0; w < backends.size(); ++w)
        threads.emplace_back([&, w] { run_worker(job, backends[w], int(w), exchange, notify); });
    for (std::thread& t : threads) t.join();
}

void run_worker_rank(MpiSession& session, const WorkerJob& job, const std::vector<std::string>& backends) {
    run_local_workers(
        job, backends, [&](const WorkMessage& m) { return session.exchange_with_coordinator(m); },
        [&](const WorkMessage& m) { session.send_to_coordinator(m); });
    WorkMessage done;
    done.kind = MessageKind::RankDone;
    session.send_to_coordinator(done);
}

nlohmann::json workers_json(const WorkCoordinator& coordinator, bool sequence) {
    nlohmann::json list = nlohmann::json::array();
    for (const WorkerRecord& w : coordinator.workers())
        list.push_back({{"rank", w.rank},
                        {"worker", w.worker},
                        {"backend", w.backend},
                        {"device", w.device},
                        {sequence ? "frames" : "tiles", w.items},
                        {"render_ms", w.render_ms}});
    return list;
}

void print_workers(const WorkCoordinator& coordinator, bool sequence) {
    for (const WorkerRecord& w : coordinator.workers())
        std::printf("  rank %d worker %d, %s [%s]: %u %s, %.1f ms rendering\n", w.rank, w.worker, w.backend.c_str(),
                    w.device.c_str(), w.items, sequence ? "frames" : "tiles", w.render_ms);
}

void report(const DistributedRender& render, const WorkerJob& job, const WorkCoordinator& coordinator, int ranks,
            double wall_ms) {
    print_workers(coordinator, job.sequence);
    FrameResult frame;
    frame.width = render.settings.width;
    frame.height = render.settings.height;
    frame.stats.frame_ms = coordinator.busy_ms();
    frame.stats.rays_per_depth = coordinator.rays_per_depth();
    frame.stats.shadow_rays_per_depth = coordinator.shadow_rays_per_depth();
    if (!job.sequence) std::printf("%s", frame_summary(frame, render.settings).c_str());
    if (render.stats.empty()) return;
    BackendInfo info;
    info.name = render.backend;
    info.device = std::to_string(coordinator.workers().size()) + " workers";
    nlohmann::json stats = frame_json(frame, render.settings, info);
    stats["scene"] = render.scene.scene;
    stats["commit"] = build_commit();
    stats["bvh"] = {{"method", render.scene.bvh},
                    {"layout", job.scene.layout},
                    {"leaf_size", render.scene.bvh_leaf_size},
                    {"node_cost", render.scene.bvh_node_cost}};
    stats["ranks"] = ranks;
    stats["workers"] = workers_json(coordinator, job.sequence);
    if (job.sequence) {
        stats["frames"] = {{"first", job.frames.first}, {"last", job.frames.last}, {"pattern", render.out}};
        stats["sequence_ms"] = coordinator.busy_ms();
    } else {
        stats["tile_size"] = render.options.tile_size;
        stats["tiles"] = job.tiles.size();
    }
    stats["wall_ms"] = wall_ms;  // with the workers' scene loading and device start-up
    write_file_atomically(render.stats, stats.dump(2) + "\n");
}

}  // namespace

void add_distributed_options(CLI::App* command, DistributedOptions& options) {
    command->add_option("--frames", options.frames,
                        "render frames A-B (or N) of a sequence; --out then names them with %d or %0Nd "
                        "(out_%04d.png)");
    command
        ->add_option("--turntable", options.turntable_seconds,
                     "with --frames: the camera turns once around its target every SECONDS")
        ->check(CLI::NonNegativeNumber);
    command->add_option("--fps", options.fps, "frames per second of a sequence (the turntable's clock)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command
        ->add_option("--tile-size", options.tile_size,
                     "pixels per side of the tiles a frame is split into over devices or MPI ranks")
        ->check(CLI::Range(1u, 1u << 16))
        ->capture_default_str();
}

bool wants_distributed_render(const std::string& backend, const DistributedOptions& options) {
    return started_as_mpi_rank() || !options.frames.empty() || options.turntable_seconds > 0.0 ||
           names_several_devices(backend);
}

void run_distributed_render(const DistributedRender& render) {
    // Bad options (and a build without MPI) fail on every rank before MPI starts; rank 0 alone says why, so the
    // user reads one line, not one per rank.
    WorkerJob job;
    std::optional<MpiSession> session;
    try {
        job = make_job(render);
        if (started_as_mpi_rank()) session.emplace();
    } catch (const Error&) {
        if (started_as_mpi_rank() && launcher_rank() > 0) std::exit(1);
        throw;
    }
    const int rank = session ? session->rank() : 0;
    const int ranks = session ? session->size() : 1;
    std::vector<std::string> backends =
        plan_local_workers(render.backend, rank, ranks, session ? session->local_rank() : 0);
    if (rank != 0) return run_worker_rank(*session, job, backends);

    auto start = Clock::now();
    const uint32_t items = job.sequence ? job.frames.count() : uint32_t(job.tiles.size());
    WorkerNaming naming = ranks > 1             ? WorkerNaming::Rank
                          : backends.size() > 1 ? WorkerNaming::Device
                                                : WorkerNaming::None;
    WorkCoordinator coordinator(items, job.tiles, render.settings.width, render.settings.height,
                                !job.sequence && needs_linear_radiance(render.format), naming);

    std::thread local([&] {
        run_local_workers(
            job, backends, [&](const WorkMessage& m) { return *coordinator.handle(0, m); },
            [&](const WorkMessage& m) { coordinator.handle(0, m); });
    });
    std::exception_ptr failure;
    try {
        for (int finished = 0; finished < ranks - 1;) {
            int source = 0;
            WorkMessage message = session->receive_from_workers(source);
            if (message.kind == MessageKind::RankDone) ++finished;
            if (std::optional<WorkMessage> answer = coordinator.handle(source, message))
                session->send_to_worker(source, *answer);
        }
    } catch (...) {
        failure = std::current_exception();
    }
    local.join();
    coordinator.workers_finished();
    if (failure) std::rethrow_exception(failure);
    coordinator.check_complete();
    double wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (!job.sequence)
        write_rendered_image(render.out, render.format, render.settings.width, render.settings.height,
                             coordinator.image(), coordinator.radiance());
    if (job.sequence)
        std::printf("prism render: %s, frames %u-%u over %d rank%s (%zu worker%s on rank 0)\n",
                    render.scene.scene.c_str(), job.frames.first, job.frames.last, ranks, ranks > 1 ? "s" : "",
                    backends.size(), backends.size() > 1 ? "s" : "");
    else
        std::printf("prism render: %s, %ux%u in %u tiles of %u over %d rank%s (%zu worker%s on rank 0)\n",
                    render.scene.scene.c_str(), render.settings.width, render.settings.height, items,
                    render.options.tile_size, ranks, ranks > 1 ? "s" : "", backends.size(),
                    backends.size() > 1 ? "s" : "");
    report(render, job, coordinator, ranks, wall_ms);
    if (job.sequence)
        std::printf("  wrote %u frames (%s) in %.0f ms\n", items, render.out.c_str(), wall_ms);
    else
        std::printf("  wrote %s (total %.0f ms)\n", render.out.c_str(), wall_ms);
}

}  // namespace prism::app
