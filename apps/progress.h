// Progress of one long step (loading a scene, building its BVH, a render's depths, benchmark runs) on stderr, with
// the time elapsed and, once the step says how far along it is, the time left. On a terminal one line is redrawn in
// place (and keeps ticking while the step gives no news); otherwise plain lines for logs, one per tenth of the step
// and one when it ends (none when it fails: the error says it); with --quiet, nothing.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "core/util/non_copyable.h"

namespace prism::app {

class Progress : private NonCopyable {
public:
    explicit Progress(std::string task);
    ~Progress();  // a step abandoned by an exception clears its line

    // `fraction` of the step is done (0 to 1); `detail` says where it stands, e.g. "depth 3/8".
    void update(double fraction, const std::string& detail = "");
    // The step is over: a plain line "<task>: done in 1.2 s"; on a terminal the line is cleared.
    void finish();

private:
    using Clock = std::chrono::steady_clock;
    std::string status_line(Clock::time_point now) const;  // callers hold mutex_
    void draw(Clock::time_point now);                      // callers hold mutex_
    void tick();

    std::string task_;
    bool enabled_ = false;
    bool terminal_ = false;
    bool finished_ = false;
    Clock::time_point start_;
    Clock::time_point last_update_;
    Clock::time_point last_draw_;
    double fraction_ = -1.0;  // negative until the step reports one
    double printed_fraction_ = -1.0;
    std::chrono::duration<double> plain_line_delay_;
    std::string detail_;
    std::mutex mutex_;
    std::condition_variable stop_;
    std::thread ticker_;
};

}  // namespace prism::app
