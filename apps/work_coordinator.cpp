#include "apps/work_coordinator.h"

#include <algorithm>
#include <span>

#include "core/util/error.h"
#include "core/render/tiles.h"

namespace prism::app {

WorkCoordinator::WorkCoordinator(uint32_t items, std::vector<PixelRect> tiles, uint32_t width, uint32_t height,
                                 bool radiance, WorkerNaming naming)
    : items_(items), tiles_(std::move(tiles)), width_(width), naming_(naming) {
    if (!tiles_.empty()) {
        image_.assign(size_t(width) * height, 0u);
        if (radiance) radiance_.assign(size_t(width) * height * 4, 0.0f);
    }
}

WorkerRecord& WorkCoordinator::record(int rank, int worker) {
    for (WorkerRecord& r : workers_)
        if (r.rank == rank && r.worker == worker) return r;
    // Kept in rank, then worker order, for the report.
    auto at = std::find_if(workers_.begin(), workers_.end(), [&](const WorkerRecord& r) {
        return r.rank > rank || (r.rank == rank && r.worker > worker);
    });
    return *workers_.insert(at, WorkerRecord{rank, worker, "", "", 0, 0.0});
}

std::string WorkCoordinator::name_of(int rank, int worker, const std::string& backend) const {
    switch (naming_) {
        case WorkerNaming::None: return "";
        case WorkerNaming::Device: return "device " + std::to_string(worker) + " (" + backend + "): ";
        case WorkerNaming::Rank:
            return "rank " + std::to_string(rank) + (worker > 0 ? " device " + std::to_string(worker) : "") + " (" +
                   backend + "): ";
    }
    return "";
}

void WorkCoordinator::add_counts(std::vector<uint32_t>& total, const std::vector<uint32_t>& counts) {
    if (total.size() < counts.size()) total.resize(counts.size(), 0u);
    for (size_t d = 0; d < counts.size(); ++d) total[d] += counts[d];
}

bool WorkCoordinator::too_slow_for_what_is_left(const WorkerRecord& asking) const {
    if (asking.items == 0) return false;  // not measured yet
    // The others' combined rate, from the items each has returned, and the items they still hold; the asker's
    // time for one item. Without the asker, the others finish what they hold and what is left in about
    // (held + left) / rate.
    double others_per_ms = 0.0, held = 0.0;
    for (const WorkerRecord& other : workers_)
        if (&other != &asking && !other.stopped && other.items > 0 && other.render_ms > 0.0) {
            others_per_ms += double(other.items) / other.render_ms;
            held += other.busy ? 1.0 : 0.0;
        }
    if (others_per_ms <= 0.0) return false;
    const double asker_ms = asking.render_ms / double(asking.items);
    const double left = double(items_ - next_);
    return asker_ms > (held + left) / others_per_ms;
}

WorkMessage WorkCoordinator::assign_next(WorkerRecord& asking) {
    WorkMessage answer;
    answer.kind = MessageKind::Assign;
    const bool give = error_.empty() && next_ < items_ && !too_slow_for_what_is_left(asking);
    answer.item = give ? int32_t(next_++) : -1;
    asking.busy = give;
    if (!give) asking.stopped = true;
    if (answer.item >= 0 && !first_assigned_) first_assigned_ = std::chrono::steady_clock::now();
    return answer;
}

std::optional<WorkMessage> WorkCoordinator::handle(int rank, const WorkMessage& message) {
    std::lock_guard lock(mutex_);
    size_t newline = message.text.find('\n');
    std::string backend = message.text.substr(0, newline);
    std::string detail = newline == std::string::npos ? "" : message.text.substr(newline + 1);
    switch (message.kind) {
        case MessageKind::Hello: {
            WorkerRecord& r = record(rank, message.worker);
            r.backend = backend;
            r.device = detail;
            return assign_next(r);
        }
        case MessageKind::Result: {
            if (message.item < 0 || uint32_t(message.item) >= items_)
                throw Error("rank " + std::to_string(rank) + " returned item " + std::to_string(message.item) +
                            " that does not exist");
            WorkerRecord& r = record(rank, message.worker);
            r.items += 1;
            r.render_ms += message.ms;
            ++done_;
            last_returned_ = std::chrono::steady_clock::now();
            add_counts(rays_, message.rays_per_depth);
            add_counts(shadow_rays_, message.shadow_rays_per_depth);
            if (!tiles_.empty()) {
                const PixelRect& tile = tiles_[size_t(message.item)];
                if (message.image.size() != tile.pixels())
                    throw Error("rank " + std::to_string(rank) + " returned a tile of the wrong size");
                place_region(std::span<uint32_t>(image_), width_, tile, std::span<const uint32_t>(message.image));
                if (!radiance_.empty() && message.radiance.size() == size_t(tile.pixels()) * 4)
                    place_region(std::span<float>(radiance_), width_, tile, std::span<const float>(message.radiance),
                                 4);
            }
            return assign_next(r);
        }
        case MessageKind::Failed:
            if (error_.empty()) error_ = name_of(rank, message.worker, backend) + detail;
            return std::nullopt;
        case MessageKind::RankDone:
        case MessageKind::Assign: return std::nullopt;
    }
    return std::nullopt;
}

double WorkCoordinator::busy_ms() const {
    if (!first_assigned_ || !last_returned_) return 0.0;
    return std::chrono::duration<double, std::milli>(*last_returned_ - *first_assigned_).count();
}

void WorkCoordinator::workers_finished() {
    std::lock_guard lock(mutex_);
    if (tiles_.empty() && last_returned_) last_returned_ = std::chrono::steady_clock::now();
}

void WorkCoordinator::check_complete() const {
    if (!error_.empty()) throw Error(error_);
    if (done_ != items_)
        throw Error("only " + std::to_string(done_) + " of " + std::to_string(items_) + " " +
                    (tiles_.empty() ? "frames" : "tiles") + " were rendered (no worker was left)");
}

}  // namespace prism::app
