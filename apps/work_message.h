// What workers and the coordinator of a split render tell each other (apps/render_distributed.cpp): inside one
// process as function calls, between MPI ranks as messages (apps/mpi_session.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace prism::app {

enum class MessageKind : int32_t {
    Hello,     // worker -> coordinator: ready (text: backend, '\n', device); asks for the first item
    Result,    // worker -> coordinator: `item` done in `ms` (tiles carry their pixels); asks for the next item
    Failed,    // worker -> coordinator: the worker stopped (text: backend, '\n', cause)
    RankDone,  // worker rank -> coordinator: every worker of the rank has stopped
    Assign,    // coordinator -> worker: render `item`, or stop when it is -1
};

struct WorkMessage {
    MessageKind kind = MessageKind::Hello;
    int32_t worker = 0;  // which of its rank's workers (one per device) sent it
    int32_t item = -1;
    double ms = 0.0;
    std::string text;
    std::vector<uint32_t> rays_per_depth, shadow_rays_per_depth;
    std::vector<uint32_t> image;  // RGBA8 of the tile
    std::vector<float> radiance;  // linear RGBA of the tile (only for .hdr output)
};

}  // namespace prism::app
