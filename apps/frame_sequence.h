// Sequences for `prism render --frames A-B`: which frames, the numbered file each one is written to, and the
// camera of each frame (a turntable around the scene camera's target).
#pragma once

#include <cstdint>
#include <string>

#include "core/scene/scene.h"

namespace prism::app {

struct FrameRange {
    uint32_t first = 0, last = 0;  // inclusive
    uint32_t count() const { return last - first + 1; }
};

// "A-B" (A <= B) or "N" (one frame). Throws prism::Error naming --frames and the cause.
FrameRange parse_frame_range(const std::string& text);

// `pattern` with its one printf-style integer field (%d or %0Nd, e.g. out_%04d.png) replaced by `frame`; "%%" is
// a literal '%'. Throws prism::Error naming --out when the pattern has no such field, or more than one.
std::string numbered_output_path(const std::string& pattern, uint32_t frame);
// Fails the same way, before any work is done.
void check_numbered_output_pattern(const std::string& pattern);

// The scene camera orbited about its `up` axis through its target: one full turn every `seconds` at `fps` frames a
// second, frame 0 being the scene camera itself. seconds <= 0 returns the camera unchanged.
Camera turntable_camera(const Camera& camera, uint32_t frame, double seconds, double fps);

}  // namespace prism::app
