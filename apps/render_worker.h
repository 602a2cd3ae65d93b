// One worker of a split render: loads the scene, opens its backend, then renders the items the coordinator hands
// it (a tile of the frame, or a whole frame of a sequence, which it writes itself) until told to stop.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "apps/frame_sequence.h"
#include "apps/render_distributed.h"
#include "apps/work_message.h"

namespace prism::app {

struct WorkerJob {
    SceneOptions scene;  // its BVH layout already fixed for every worker (shared_bvh_layout)
    RenderSettings settings;
    std::vector<PixelRect> tiles;  // the items when not a sequence
    bool sequence = false;
    FrameRange frames;                       // the items of a sequence: frames.first + item
    std::string out;                         // the image, or the numbered pattern of a sequence
    ImageFormat format = ImageFormat::Png8;  // of out (core/image/image_output.h)
    DistributedOptions options;
};

// `exchange` sends a message and returns the coordinator's Assign; `notify` sends one that has no answer. Every
// failure (the scene, the device, a frame) ends as one Failed message, never as an exception.
void run_worker(const WorkerJob& job, const std::string& backend, int worker,
                const std::function<WorkMessage(const WorkMessage&)>& exchange,
                const std::function<void(const WorkMessage&)>& notify);

// Writes a rendered image in the format --out asked for (PNG 8/16-bit, EXR or HDR).
void write_rendered_image(const std::string& path, ImageFormat format, uint32_t width, uint32_t height,
                          const std::vector<uint32_t>& image, const std::vector<float>& radiance);

}  // namespace prism::app
