#include "viewer/frame_display.h"

#include "core/util/error.h"
#include "viewer/interop_display.h"
#include "viewer/texture_quad.h"

namespace prism::viewer {
namespace {

// The host-copy path: the frame's RGBA8 bytes go into a texture with glTexSubImage2D every frame.
class HostCopyDisplay final : public FrameDisplay {
public:
    explicit HostCopyDisplay(DisplayPath path) : path_(std::move(path)) {}

    const DisplayPath& path() const override { return path_; }

    void update(const FrameResult& frame) override {
        if (frame.image.size() != size_t(frame.width) * frame.height)
            throw Error("view: frame has " + std::to_string(frame.image.size()) + " pixels, expected " +
                        std::to_string(size_t(frame.width) * frame.height));
        quad_.upload_from_host(frame.width, frame.height, frame.image.data());
    }

    void draw(int viewport_width, int viewport_height) override { quad_.draw(viewport_width, viewport_height); }

private:
    DisplayPath path_;
    TextureQuad quad_;
};

// --display none: frames are rendered and stay on the device; the window keeps whatever it showed.
class NoDisplay final : public FrameDisplay {
public:
    explicit NoDisplay(DisplayPath path) : path_(std::move(path)) {}
    const DisplayPath& path() const override { return path_; }
    void update(const FrameResult&) override {}
    void draw(int, int) override {}

private:
    DisplayPath path_;
};

}  // namespace

DisplayMode parse_display_mode(const std::string& text) {
    if (text == "auto") return DisplayMode::Auto;
    if (text == "interop") return DisplayMode::Interop;
    if (text == "host-copy") return DisplayMode::HostCopy;
    if (text == "none") return DisplayMode::None;
    throw Error("view: --display '" + text + "' is not one of auto, interop, host-copy, none");
}

const char* display_mode_name(DisplayMode mode) {
    switch (mode) {
        case DisplayMode::Auto: return "auto";
        case DisplayMode::Interop: return "interop";
        case DisplayMode::HostCopy: return "host-copy";
        case DisplayMode::None: return "none";
    }
    return "?";
}

std::string DisplayPath::describe() const {
    switch (kind) {
        case Kind::HostCopy: return "interop: host copy (" + detail + ")";
        case Kind::Interop: return "interop: " + name + " (sync: " + detail + ")";
        case Kind::None: return "display: none (" + detail + ")";
    }
    return "?";
}

const char* DisplayPath::kind_name() const {
    switch (kind) {
        case Kind::HostCopy: return "host-copy";
        case Kind::Interop: return "interop";
        case Kind::None: return "none";
    }
    return "?";
}

DisplayPath choose_display_path(DisplayMode mode, const BackendInfo& backend, const GlInteropOffer& offer) {
    using Kind = DisplayPath::Kind;
    switch (mode) {
        case DisplayMode::None: return {Kind::None, "none", "--display none: frames are rendered, not shown"};
        case DisplayMode::HostCopy: return {Kind::HostCopy, "host copy", "--display host-copy"};
        case DisplayMode::Auto:
        case DisplayMode::Interop:
            if (offer.interop) return {Kind::Interop, offer.interop->name(), offer.interop->sync()};
            if (mode == DisplayMode::Interop)
                throw Error("view: --display interop: no GL interop for " + backend.name + " [" + backend.device +
                            "] (" + offer.reason + ")");
            return {Kind::HostCopy, "host copy", offer.reason};
    }
    return {Kind::HostCopy, "host copy", "?"};
}

std::unique_ptr<FrameDisplay> open_frame_display(DisplayMode mode, DisplayPath path, GlInterop* interop, uint32_t width,
                                                 uint32_t height) {
    switch (path.kind) {
        case DisplayPath::Kind::None: return std::make_unique<NoDisplay>(std::move(path));
        case DisplayPath::Kind::HostCopy: return std::make_unique<HostCopyDisplay>(std::move(path));
        case DisplayPath::Kind::Interop: break;
    }
    try {
        return create_interop_display(path, *interop, width, height);
    } catch (const Error& e) {
        if (mode == DisplayMode::Interop) throw Error("view: --display interop: " + path.name + ": " + e.what());
        return std::make_unique<HostCopyDisplay>(
            DisplayPath{DisplayPath::Kind::HostCopy, "host copy", path.name + " failed: " + e.what()});
    }
}

void set_read_back(const DisplayPath& path, RenderSettings& settings, bool shown) {
    settings.read_image = shown && path.kind == DisplayPath::Kind::HostCopy;
    settings.copy_to_gl = shown && path.kind == DisplayPath::Kind::Interop;
    settings.read_radiance = false;  // the viewer shows the tone-mapped image only
}

}  // namespace prism::viewer
