#include "bench/bandwidth/sweep.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>

#include "bench/bandwidth/pci_link.h"
#include "bench/bandwidth/sizes.h"
#include "core/util/error.h"

namespace prism::bandwidth {
namespace {

// Ordinary malloc'd host memory, page aligned and touched, as an application's own buffers would be.
struct PageableBuffer {
    std::unique_ptr<std::byte, decltype(&std::free)> memory{nullptr, &std::free};
    explicit PageableBuffer(size_t bytes) {
        size_t rounded = (bytes + 4095) / 4096 * 4096;
        memory.reset(static_cast<std::byte*>(std::aligned_alloc(4096, rounded)));
        if (!memory) throw SizeSkipped("out of host memory for the pageable buffer");
        std::memset(memory.get(), 0, rounded);
    }
    std::byte* data() const { return memory.get(); }
};

// A pattern that differs per word and per seed, so a missed or misplaced copy cannot pass.
void fill_pattern(std::byte* data, size_t bytes, uint32_t seed) {
    auto* words = reinterpret_cast<uint32_t*>(data);
    for (size_t i = 0; i < bytes / 4; ++i) words[i] = static_cast<uint32_t>(i) * 2654435761u + seed;
}

bool has_pattern(const std::byte* data, size_t bytes, uint32_t seed) {
    const auto* words = reinterpret_cast<const uint32_t*>(data);
    for (size_t i = 0; i < bytes / 4; ++i)
        if (words[i] != static_cast<uint32_t>(i) * 2654435761u + seed) return false;
    return true;
}

// Free host memory (MemAvailable), or 0 when unknown.
size_t host_memory_available() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    size_t kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024;
    return 0;
}

class SizeRun {
public:
    SizeRun(CopyDevice& device, const Plan& plan, DeviceResult& result, size_t bytes)
        : device_(device), plan_(plan), result_(result), bytes_(bytes) {}

    void note(const std::string& text) { result_.notes.push_back(format_size(bytes_) + ": " + text); }

    // Warm-up, then `repeats` timed copies; keeps the measurement when `check` (run after the last copy) passes.
    void measure(Direction direction, Memory memory, const std::function<Timed()>& copy,
                 const std::function<bool()>& check) {
        std::string what = std::string(direction_label(direction)) + " " + memory_key(memory);
        if (!queue_.empty()) what += " on the " + queue_ + " queue";
        try {
            for (int i = 0; i < plan_.warmup; ++i) copy();
            std::vector<double> device_seconds, wall_seconds;
            bool device_timer = true;
            for (int i = 0; i < plan_.repeats; ++i) {
                Timed timed = copy();
                wall_seconds.push_back(timed.wall_seconds);
                if (timed.device_seconds && *timed.device_seconds > 0)
                    device_seconds.push_back(*timed.device_seconds);
                else
                    device_timer = false;
            }
            if (!check()) {
                note(what + ": wrong data after the copy; measurement dropped");
                return;
            }
            Measurement measurement{direction, memory, bytes_, queue_, std::nullopt, summarize(bytes_, wall_seconds)};
            if (device_timer) measurement.device_timer = summarize(bytes_, device_seconds);
            result_.measurements.push_back(measurement);
        } catch (const SizeSkipped& skipped) {
            note(what + ": skipped: " + skipped.what());
        }
    }

    void run() {
        PageableBuffer pageable(bytes_);
        device_.allocate(bytes_, pageable.data());
        // Every copy command on each queue: each pass leaves its own checked data in A for the D2D copy.
        for (const std::string& queue : device_.copy_queues()) {
            queue_ = queue;
            device_.use_copy_queue(queue);
            measure_copy_commands(pageable.data());
        }
        // The kernel is a dispatch: it runs on the compute queue whatever queue the copies used.
        queue_.clear();
        std::string kernel_limit = device_.kernel_cannot_fit(bytes_);
        if (!kernel_limit.empty()) {
            note(std::string(direction_label(Direction::KernelCopy)) + ": skipped: " + kernel_limit);
        } else {
            device_.clear_destination();
            measure(
                Direction::KernelCopy, Memory::Device, [&] { return device_.copy_kernel(); },
                [&] { return destination_holds_a(pageable.data()); });
        }
    }

    // A holds pattern 3 after measure_copy_commands(); a device copy must reproduce it in B.
    bool destination_holds_a(std::byte* host) {
        std::memset(host, 0, bytes_);
        device_.read_destination();
        return has_pattern(host, bytes_, 3);
    }

    void measure_copy_commands(std::byte* host) {
        std::byte* pinned_upload = device_.pinned_upload();
        std::byte* pinned_download = device_.pinned_download();
        // Seeds differ so each check proves both the upload before it and the download it follows. The pinned
        // pattern is written after the pageable upload: on Vulkan that upload goes through the same staging memory.
        fill_pattern(host, bytes_, 1);
        measure(
            Direction::HostToDevice, Memory::Pageable, [&] { return device_.upload(Memory::Pageable); },
            [] { return true; });
        fill_pattern(pinned_upload, bytes_, 2);
        measure(
            Direction::HostToDevice, Memory::Pinned, [&] { return device_.upload(Memory::Pinned); },
            [] { return true; });
        std::memset(host, 0, bytes_);
        measure(
            Direction::DeviceToHost, Memory::Pageable, [&] { return device_.download(Memory::Pageable); },
            [&] { return has_pattern(host, bytes_, 2); });
        fill_pattern(host, bytes_, 3);
        device_.upload(Memory::Pageable);
        std::memset(pinned_download, 0, bytes_);
        measure(
            Direction::DeviceToHost, Memory::Pinned, [&] { return device_.download(Memory::Pinned); },
            [&] { return has_pattern(pinned_download, bytes_, 3); });
        read_link();

        device_.clear_destination();
        measure(
            Direction::DeviceToDevice, Memory::Device, [&] { return device_.copy_buffer(); },
            [&] { return destination_holds_a(host); });
    }

    // The link trains down when idle; read it right after traffic and keep the fastest seen.
    void read_link() {
        if (result_.pci_address.empty()) return;
        std::optional<LinkInfo> link = read_pci_link(result_.pci_address);
        if (link && (!result_.link || link->gbps > result_.link->gbps)) result_.link = link;
    }

private:
    CopyDevice& device_;
    const Plan& plan_;
    DeviceResult& result_;
    size_t bytes_;
    std::string queue_;  // the queue of the copies being measured, recorded in each Measurement
};

}  // namespace

DeviceResult sweep(CopyDevice& device, const Plan& plan) {
    DeviceResult result = device.describe();
    for (size_t bytes : plan.sizes) {
        SizeRun run(device, plan, result, bytes);
        std::string limit = device.cannot_fit(bytes);
        // Pageable buffer, pinned/staging memory, and device memory that may itself be host memory (CPU devices).
        size_t available = host_memory_available();
        if (limit.empty() && available && 4 * bytes > available)
            limit =
                "needs about " + format_size(4 * bytes) + " of host memory, " + format_size(available) + " available";
        if (!limit.empty()) {
            run.note("skipped: " + limit);
            continue;
        }
        try {
            run.run();
        } catch (const SizeSkipped& skipped) {
            run.note(std::string("skipped: ") + skipped.what());
        } catch (const Error& error) {
            run.note(std::string("failed: ") + error.what());
        }
        device.release();
    }
    // Fields the device learns while running (e.g. the driver's link) come from describe(); keep the sweep's.
    DeviceResult after = device.describe();
    after.notes = std::move(result.notes);
    after.measurements = std::move(result.measurements);
    if (result.link) after.link = result.link;
    return after;
}

}  // namespace prism::bandwidth
