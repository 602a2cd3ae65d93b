// Checks of the options a run takes that need no scene, made before any work: a run that is going to fail
// fails at once, names the option, and writes nothing.
#pragma once

#include <string>

#include "core/render/renderer.h"

namespace prism::app {

// cpu and cpu-ref have one device: only "cpu:0" / "cpu-ref:0" name it.
void check_backend_option(const std::string& backend);
// A weight threshold: a number in [0, 1].
void check_min_weight_option(float min_weight);
// That `path` can be created or replaced, by creating (and removing) a file beside it: permission bits alone do
// not say it (root ignores them; a read-only mount or a missing folder does not). `option` names it ("--out").
void check_writable_option(const std::string& option, const std::string& path);

// The frame a run will render, on one backend: the backend's device, frame size and depth, min weight, and the
// host memory the frame needs there (PRISM_HOST_MEMORY_LIMIT lowers the limit). `prism view` and `prism bench`
// check it before loading; `prism render` as part of check_render_options.
void check_frame_options(const std::string& backend, const RenderSettings& settings);

// Everything `prism render` can check before loading: backend, frame size and depth, min weight, the host memory
// the frame needs on that backend, and both output paths (different, writable).
void check_render_options(const std::string& backend, const RenderSettings& settings, const std::string& out,
                          const std::string& stats);

}  // namespace prism::app
