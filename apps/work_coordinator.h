// Rank 0's side of a split render: hands out items (tiles or frames) in order to whichever worker asks next, so a
// slow device takes fewer; puts returned tiles into the image; keeps each worker's device, items and time; stops
// handing out work after the first failure and keeps that failure's message.
// Near the end, a worker is sent home rather than given an item it would finish after the others have finished
// everything left: a CPU beside a GPU must not hold the frame up with its last tile (too_slow_for_what_is_left).
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "apps/work_message.h"
#include "core/render/renderer.h"

namespace prism::app {

struct WorkerRecord {
    int rank = 0, worker = 0;
    std::string backend, device;
    uint32_t items = 0;
    double render_ms = 0.0;  // wall time of its items, rendering only
    bool stopped = false;    // told to stop (no items left, a failure, or too slow for what was left)
    bool busy = false;       // holds an item it has not returned
};

// How a failing worker is named in the error: not at all (one worker), "device W" (one process) or "rank R".
enum class WorkerNaming { None, Device, Rank };

class WorkCoordinator {
public:
    // `tiles` empty: the items are frames, written by the workers; else the items are these tiles of an image of
    // `width` x `height` (linear radiance kept too when `radiance`).
    WorkCoordinator(uint32_t items, std::vector<PixelRect> tiles, uint32_t width, uint32_t height, bool radiance,
                    WorkerNaming naming);

    // The answer to a worker's message: Assign (an item, or -1 to stop) for Hello and Result; none for Failed and
    // RankDone. Safe to call from several threads.
    std::optional<WorkMessage> handle(int rank, const WorkMessage& message);

    // After every worker has stopped. Throws prism::Error with the first failure, or when items are missing.
    void check_complete() const;

    // Wall time from the first item handed out to the last one returned: the frame's (or sequence's) time without
    // the workers' scene loading and device start-up.
    double busy_ms() const;
    // Every worker has returned: a sequence's busy time then runs to here, since its workers write their last
    // frames after returning them (apps/frame_writer.h).
    void workers_finished();
    const std::vector<WorkerRecord>& workers() const { return workers_; }
    const std::vector<uint32_t>& image() const { return image_; }
    const std::vector<float>& radiance() const { return radiance_; }
    const std::vector<uint32_t>& rays_per_depth() const { return rays_; }
    const std::vector<uint32_t>& shadow_rays_per_depth() const { return shadow_rays_; }

private:
    WorkerRecord& record(int rank, int worker);
    std::string name_of(int rank, int worker, const std::string& backend) const;
    void add_counts(std::vector<uint32_t>& total, const std::vector<uint32_t>& counts);
    WorkMessage assign_next(WorkerRecord& asking);
    bool too_slow_for_what_is_left(const WorkerRecord& asking) const;

    std::mutex mutex_;
    std::optional<std::chrono::steady_clock::time_point> first_assigned_, last_returned_;
    uint32_t items_, next_ = 0, done_ = 0;
    std::vector<PixelRect> tiles_;
    uint32_t width_;
    WorkerNaming naming_;
    std::string error_;
    std::vector<WorkerRecord> workers_;
    std::vector<uint32_t> image_;
    std::vector<float> radiance_;
    std::vector<uint32_t> rays_, shadow_rays_;
};

}  // namespace prism::app
