#include "apps/progress.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>

#include <unistd.h>

#include "apps/cli_conventions.h"
#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism::app {
namespace {

std::string seconds(double value) {
    char text[32];
    if (value < 10.0)
        std::snprintf(text, sizeof text, "%.2f s", value);
    else if (value < 120.0)
        std::snprintf(text, sizeof text, "%.1f s", value);
    else
        std::snprintf(text, sizeof text, "%d min %02d s", int(value) / 60, int(value) % 60);
    return text;
}

// How long a step runs before its plain lines start (PRISM_PROGRESS_DELAY seconds, default 1): a step shorter
// than that prints only its "done" line, so a small scene's log is not a screen of percentages.
std::chrono::duration<double> plain_line_delay() {
    std::optional<std::string> text = setting(Setting::ProgressDelay);
    if (!text || text->empty()) return std::chrono::duration<double>(1.0);
    char* end = nullptr;
    double value = std::strtod(text->c_str(), &end);
    if (end == text->c_str() || *end != '\0' || !(value >= 0.0 && value <= 3600.0))
        throw Error(std::string(setting_name(Setting::ProgressDelay)) + "='" + shorten(*text) +
                    "' is not a number of seconds from 0 to 3600");
    return std::chrono::duration<double>(value);
}

}  // namespace

Progress::Progress(std::string task)
    : task_(std::move(task)),
      enabled_(!quiet()),
      terminal_(isatty(STDERR_FILENO)),
      start_(Clock::now()),
      last_update_(start_),
      plain_line_delay_(plain_line_delay()) {
    if (!enabled_) return;
    // Plain lines start at the first news: a step that fails at once leaves only its one-line error.
    if (!terminal_) return;
    std::lock_guard lock(mutex_);
    draw(start_);
    ticker_ = std::thread([this] { tick(); });
}

Progress::~Progress() {
    if (!finished_ && enabled_ && terminal_) {
        {
            std::lock_guard lock(mutex_);
            finished_ = true;
        }
        stop_.notify_all();
        ticker_.join();
        std::fprintf(stderr, "\r\033[K");
    }
}

void Progress::update(double fraction, const std::string& detail) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    Clock::time_point now = Clock::now();
    fraction_ = std::clamp(fraction, 0.0, 1.0);
    detail_ = detail;
    last_update_ = now;
    if (terminal_) {
        if (now - last_draw_ >= std::chrono::milliseconds(100) || fraction_ >= 1.0) draw(now);
    } else if (now - start_ >= plain_line_delay_ &&
               (fraction_ >= printed_fraction_ + 0.1 || (fraction_ >= 1.0 && printed_fraction_ < 1.0))) {
        // Plain lines for logs: about every tenth of a long step, however often it reports.
        printed_fraction_ = fraction_;
        std::fprintf(stderr, "prism: %s\n", status_line(now).c_str());
    }
}

void Progress::finish() {
    if (!enabled_ || finished_) return;
    {
        std::lock_guard lock(mutex_);
        finished_ = true;
    }
    double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    if (terminal_) {
        stop_.notify_all();
        ticker_.join();
        std::fprintf(stderr, "\r\033[K");
    } else {
        std::fprintf(stderr, "prism: %s: done in %s\n", task_.c_str(), seconds(elapsed).c_str());
    }
    std::fflush(stderr);
}

std::string Progress::status_line(Clock::time_point now) const {
    double elapsed = std::chrono::duration<double>(now - start_).count();
    std::string line = task_;
    if (!detail_.empty()) line += ": " + detail_;
    if (fraction_ >= 0.0) line += " (" + std::to_string(int(fraction_ * 100.0 + 0.5)) + "%)";
    line += ", " + seconds(elapsed) + " elapsed";
    if (fraction_ > 0.0) {
        // The rate of the last report, less the time since: the estimate counts down between reports.
        double at_update = std::chrono::duration<double>(last_update_ - start_).count();
        double left =
            at_update * (1.0 - fraction_) / fraction_ - std::chrono::duration<double>(now - last_update_).count();
        line += ", ETA " + seconds(std::max(left, 0.0));
    }
    return line;
}

void Progress::draw(Clock::time_point now) {
    last_draw_ = now;
    std::string bar;
    if (fraction_ >= 0.0) {
        const int width = 20, filled = int(fraction_ * width + 0.5);
        bar = "[" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), ' ') + "] ";
    }
    std::fprintf(stderr, "\r\033[K  %s%s", bar.c_str(), status_line(now).c_str());
    std::fflush(stderr);
}

void Progress::tick() {
    std::unique_lock lock(mutex_);
    while (!finished_) {
        stop_.wait_for(lock, std::chrono::milliseconds(250));
        if (!finished_) draw(Clock::now());
    }
}

}  // namespace prism::app
