// The GPU time of the display's GL commands (texture upload or interop upload, and the draw) per frame, from
// GL_TIME_ELAPSED queries. Results are collected a few frames later, so measuring never makes the viewer wait for
// GL (a glFinish per frame costs about 0.3 ms on the H100 and would be charged to the display path).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "core/util/non_copyable.h"
#include "viewer/gl.h"

namespace prism::viewer {

class GlTimer : private NonCopyable {
public:
    GlTimer();
    ~GlTimer();

    // Brackets one frame's display commands; `frame` is returned with its result.
    void begin(size_t frame);
    void end();
    // (frame, GPU milliseconds) of the queries that have finished; with `wait`, of all issued ones.
    std::vector<std::pair<size_t, double>> collect(bool wait);

private:
    static constexpr size_t kQueries = 4;  // in flight at once: a frame's result is read 3 frames later
    GLuint queries_[kQueries] = {};
    size_t frame_of_[kQueries] = {};
    bool pending_[kQueries] = {};
    size_t next_ = 0;
};

}  // namespace prism::viewer
