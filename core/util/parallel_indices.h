// Short-lived parallel loops for one-off passes (the BVH build's), where a persistent ThreadPool would outlive
// the work: threads are started for the call and joined before it returns.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

namespace prism {

// Runs job(i) for every i in [0, count) on up to `threads` threads (the caller's among them), each thread taking
// the next i when it is free. Returns when all are done.
template <class Job>
void for_each_index_on_threads(uint32_t threads, size_t count, const Job& job) {
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < count; i = next++) job(i);
    };
    std::vector<std::thread> helpers;
    for (uint32_t t = 1; t < std::min<size_t>(threads, count); ++t) helpers.emplace_back(work);
    work();
    for (auto& helper : helpers) helper.join();
}

}  // namespace prism
