// Writes the frames of a sequence on background threads, so a worker renders frame N+1 while frame N is encoded
// (a 1080p PNG takes several times longer to compress than a GPU takes to render it). At most `max_pending`
// frames wait at once, which bounds the memory they hold; submit() blocks beyond that.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/image/image_output.h"
#include "core/util/non_copyable.h"

namespace prism::app {

struct PendingFrame {
    std::string path;
    ImageFormat format = ImageFormat::Png8;
    uint32_t width = 0, height = 0;
    std::vector<uint32_t> image;
    std::vector<float> radiance;
};

class FrameWriter : private NonCopyable {
public:
    // threads: encoders; 0 picks a quarter of the host's cores, 1 to 4.
    explicit FrameWriter(unsigned threads = 0);
    ~FrameWriter();  // drops what was not finished; call finish() to keep it

    // Queues a frame; throws the first failed write (a full disk stops the sequence at the next frame).
    void submit(PendingFrame frame);
    // Waits until every queued frame is written; throws the first failed write.
    void finish();

private:
    void encode_loop();
    void rethrow_failure();

    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<PendingFrame> queue_;
    size_t max_pending_ = 1;
    size_t writing_ = 0;
    bool stopping_ = false;
    std::exception_ptr failure_;
    std::vector<std::thread> threads_;
};

}  // namespace prism::app
