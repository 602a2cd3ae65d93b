#include "apps/frame_writer.h"

#include <algorithm>

namespace prism::app {

FrameWriter::FrameWriter(unsigned threads) {
    if (threads == 0) threads = std::clamp(std::thread::hardware_concurrency() / 4, 1u, 4u);
    max_pending_ = threads + 1;
    for (unsigned i = 0; i < threads; ++i) threads_.emplace_back([this] { encode_loop(); });
}

FrameWriter::~FrameWriter() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        queue_.clear();
    }
    changed_.notify_all();
    for (std::thread& thread : threads_) thread.join();
}

void FrameWriter::rethrow_failure() {
    if (failure_) std::rethrow_exception(failure_);
}

void FrameWriter::submit(PendingFrame frame) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return failure_ || queue_.size() < max_pending_; });
    rethrow_failure();
    queue_.push_back(std::move(frame));
    lock.unlock();
    changed_.notify_all();
}

void FrameWriter::finish() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return failure_ || (queue_.empty() && writing_ == 0); });
    rethrow_failure();
}

void FrameWriter::encode_loop() {
    for (;;) {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (stopping_) return;
        PendingFrame frame = std::move(queue_.front());
        queue_.pop_front();
        ++writing_;
        lock.unlock();
        changed_.notify_all();  // a place in the queue is free
        std::exception_ptr failed;
        try {
            write_image(frame.path, frame.format, int(frame.width), int(frame.height), frame.image, frame.radiance);
        } catch (...) {
            failed = std::current_exception();
        }
        lock.lock();
        --writing_;
        if (failed && !failure_) failure_ = failed;
        lock.unlock();
        changed_.notify_all();
    }
}

}  // namespace prism::app
