// A fixed set of worker threads that run one job at a time on all workers (the cpu backend's launches, the
// reference renderer's tiles). Persistent threads: a frame makes dozens of launches, and creating threads for
// each would cost more than the small ones take.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "core/util/non_copyable.h"

namespace prism {

class ThreadPool : private NonCopyable {
public:
    explicit ThreadPool(unsigned threads = 0);  // 0: std::thread::hardware_concurrency()
    ~ThreadPool();

    unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }
    // Runs job(worker) on every worker (the calling thread is worker 0) and returns when all are done.
    // The first exception thrown by any worker is rethrown here.
    void run(const std::function<void(unsigned worker)>& job);

private:
    void worker_loop(unsigned worker);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable start_;
    std::condition_variable done_;
    const std::function<void(unsigned)>* job_ = nullptr;
    uint64_t generation_ = 0;
    unsigned pending_ = 0;
    bool stopping_ = false;
    std::exception_ptr error_;
};

}  // namespace prism
