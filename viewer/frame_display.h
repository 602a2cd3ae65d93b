// How a rendered frame reaches the window. One implementation per display path:
//   host copy - glTexSubImage2D from FrameResult.image (every backend; the fallback);
//   interop   - the backend's image array copied on the device, at the end of the frame's own submission, into a
//               GL buffer it shares with GL (CUDA-GL, OpenCL-GL, Vulkan-GL: core/render/gl_interop.h,
//               viewer/interop_display.h), which the draw reads directly (a buffer texture);
//   none      - nothing is shown: `--display none` measures the render alone.
// choose_display_path() decides from what the user asked and what the backend offers, and says why;
// open_frame_display() builds it, falling back to the host copy when an interop path fails to set up.
#pragma once

#include <memory>
#include <string>

#include "core/render/backend.h"
#include "core/render/gl_interop.h"
#include "core/render/renderer.h"

namespace prism::viewer {

// --display: auto (interop where the backend and GL offer it, else host copy), interop (required), host-copy
// (forced, e.g. to measure against interop), none (render only, not shown).
enum class DisplayMode { Auto, Interop, HostCopy, None };
DisplayMode parse_display_mode(const std::string& text);  // throws prism::Error naming the choices
const char* display_mode_name(DisplayMode mode);          // "auto", "interop", "host-copy", "none"

struct DisplayPath {
    enum class Kind { HostCopy, Interop, None };
    Kind kind = Kind::HostCopy;
    std::string name;    // "host copy", "CUDA-GL", "OpenCL-GL", "Vulkan-GL", "none"
    std::string detail;  // host copy: why not interop; interop: how device and GL are synchronised; none: why
    // What the HUD and the console show: "interop: host copy (PoCL has no cl_khr_gl_sharing)",
    // "interop: CUDA-GL (sync: map/unmap on the CUDA stream ...)", "display: none (--display none: render only)".
    std::string describe() const;
    const char* kind_name() const;  // "host-copy", "interop", "none" (the --stats JSON)
};

// Throws prism::Error for DisplayMode::Interop when `offer` has no interop ("view: --display interop: ...").
DisplayPath choose_display_path(DisplayMode mode, const BackendInfo& backend, const GlInteropOffer& offer);

class FrameDisplay {
public:
    virtual ~FrameDisplay() = default;
    virtual const DisplayPath& path() const = 0;
    // Makes `frame` the displayed image (the GL context must be current). The interop paths take the pixels from
    // the shared buffer the frame's own submission copied the image into, not from frame.image.
    virtual void update(const FrameResult& frame) = 0;
    // Draws the displayed image over the whole viewport of the bound framebuffer.
    virtual void draw(int viewport_width, int viewport_height) = 0;
};

// Builds the display for `path` (`interop`: the offer's, for an interop path) for frames of width x height.
// When an interop path cannot be set up (the driver refuses to share the buffer), DisplayMode::Auto falls back
// to the host copy, its reason naming the failure; DisplayMode::Interop throws prism::Error.
// Needs a current GL 3.3+ core context.
std::unique_ptr<FrameDisplay> open_frame_display(DisplayMode mode, DisplayPath path, GlInterop* interop, uint32_t width,
                                                 uint32_t height);

// The RenderSettings::read_image / read_radiance / copy_to_gl a path needs: the image read back for the host copy,
// the copy into GL's buffer for interop, nothing for none. `shown` false: this frame is only rendered (nothing).
void set_read_back(const DisplayPath& path, RenderSettings& settings, bool shown = true);

}  // namespace prism::viewer
