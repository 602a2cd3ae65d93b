#include "viewer/gl_timer.h"

namespace prism::viewer {

GlTimer::GlTimer() { glGenQueries(GLsizei(kQueries), queries_); }

GlTimer::~GlTimer() { glDeleteQueries(GLsizei(kQueries), queries_); }

void GlTimer::begin(size_t frame) {
    // The slot's previous query is 4 frames old: read back by collect(), or read now (it has long finished).
    if (pending_[next_]) collect(true);
    frame_of_[next_] = frame;
    glBeginQuery(GL_TIME_ELAPSED, queries_[next_]);
}

void GlTimer::end() {
    glEndQuery(GL_TIME_ELAPSED);
    pending_[next_] = true;
    next_ = (next_ + 1) % kQueries;
}

std::vector<std::pair<size_t, double>> GlTimer::collect(bool wait) {
    std::vector<std::pair<size_t, double>> results;
    for (size_t i = 0; i < kQueries; ++i) {
        size_t slot = (next_ + i) % kQueries;  // oldest first
        if (!pending_[slot]) continue;
        GLint available = GL_FALSE;
        if (!wait) glGetQueryObjectiv(queries_[slot], GL_QUERY_RESULT_AVAILABLE, &available);
        if (!wait && !available) continue;
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(queries_[slot], GL_QUERY_RESULT, &nanoseconds);
        pending_[slot] = false;
        results.emplace_back(frame_of_[slot], double(nanoseconds) * 1e-6);
    }
    return results;
}

}  // namespace prism::viewer
