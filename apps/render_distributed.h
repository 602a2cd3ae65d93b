// `prism render` over several devices or MPI ranks: one frame split into tiles that workers take from a queue, or
// a sequence (--frames A-B) whose frames workers take one at a time. Without mpirun the same command runs its
// workers in one process (one per --backend entry or device of "<api>:all"), so a farm scheduler can give each job
// a frame range.
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "apps/scene_options.h"
#include "core/image/image_output.h"
#include "core/render/renderer.h"

namespace prism::app {

struct DistributedOptions {
    std::string frames;              // "A-B" or "N": a sequence, --out holding %04d
    double turntable_seconds = 0.0;  // a turn of the camera around its target every this many seconds
    double fps = 24.0;
    uint32_t tile_size = 128;
};

void add_distributed_options(CLI::App* command, DistributedOptions& options);

// Under mpirun, a sequence (or --turntable), a --backend list or "<api>:all": the render goes through
// run_distributed_render.
bool wants_distributed_render(const std::string& backend, const DistributedOptions& options);

struct DistributedRender {
    SceneOptions scene;
    std::string backend;
    RenderSettings settings;  // read_radiance already set for the output format
    std::string out;
    ImageFormat format;  // of --out, checked before any work (core/image/image_output.h)
    std::string stats;
    DistributedOptions options;
};

// Rank 0 (or the one process) writes the image, or each worker its frames; a failed worker fails the whole run
// with prism::Error "rank R (backend): cause" and no image.
void run_distributed_render(const DistributedRender& render);

}  // namespace prism::app
