// `prism view`: the interactive preview. This file drives it — scene, RenderEngine, backend switching, the moving
// object, the HUD text — and viewer/ does the window, input and display. Without GLFW/OpenGL at configure time
// the command still exists and says why it cannot run.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/frame_report.h"
#include "apps/scene_options.h"
#include "core/build_info.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/output_file.h"
#include "core/render_engine.h"

#ifdef PRISM_HAVE_VIEWER
#include <chrono>

#include <glm/gtc/matrix_transform.hpp>

#include "viewer/camera_controls.h"
#include "viewer/frame_display.h"
#include "viewer/frame_timing.h"
#include "viewer/gl_timer.h"
#include "viewer/key_script.h"
#include "viewer/window.h"
#endif

namespace prism::app {
namespace {

struct ViewOptions {
    SceneOptions scene;
    std::string backend = "auto";
    RenderSettings settings;
    uint32_t frames = 0;      // 0: until Esc or the window closes
    double seconds = 0.0;     // > 0: also stop after this much wall-clock time (bench/soak_viewer.sh)
    std::string screenshot;   // with --frames: the last frame, read back from the window
    bool no_vsync = false;
    std::string keys;         // scripted key presses, "FRAME:KEY,..."
    std::string display = "auto";   // auto, interop, host-copy, none (viewer/frame_display.h)
    std::string stats;        // --stats: the timing summary as JSON
    bool headless = false;    // an offscreen EGL framebuffer instead of a window (viewer/offscreen_window.h)
    uint32_t alternate = 0;   // --alternate-display N: N frames shown, N only rendered, ... (0: every frame shown)
};

#ifdef PRISM_HAVE_VIEWER

using viewer::Action;

// One instance turning about its own vertical axis and swinging left and right, advanced per frame (not per
// second) so a scripted run is reproducible. Only the top level changes: RenderEngine refits it.
class MovingObject {
public:
    explicit MovingObject(const LoadedScene& loaded) {
        for (const Instance& instance : loaded.scene.instances) base_.push_back(instance.transform);
        if (base_.empty()) return;
        index_ = base_.size() - 1;   // the loaders and builtin scenes add the floor first and the model last
        const Aabb& bounds = loaded.device.mesh_bounds.at(loaded.device.instance_meshes.at(index_));
        Aabb world;
        for (int corner = 0; corner < 8; ++corner) {
            glm::vec3 p{corner & 1 ? bounds.upper.x : bounds.lower.x, corner & 2 ? bounds.upper.y : bounds.lower.y,
                        corner & 4 ? bounds.upper.z : bounds.lower.z};
            world.grow(glm::vec3(base_[index_] * glm::vec4(p, 1.0f)));
        }
        centre_ = world.center();
        glm::vec3 extent = world.upper - world.lower;
        amplitude_ = 0.5f * std::max(extent.x, extent.z);
        name_ = loaded.scene.instances[index_].name;
    }

    bool empty() const { return base_.empty(); }
    const std::string& name() const { return name_; }

    std::vector<glm::mat4> advance() {
        ++step_;
        float angle = 0.15f * float(step_);
        glm::vec3 offset{amplitude_ * std::sin(angle), 0.0f, 0.0f};
        std::vector<glm::mat4> transforms = base_;
        transforms[index_] = glm::translate(glm::mat4(1.0f), centre_ + offset) *
                             glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0.0f, 1.0f, 0.0f)) *
                             glm::translate(glm::mat4(1.0f), -centre_) * base_[index_];
        return transforms;
    }

private:
    std::vector<glm::mat4> base_;
    size_t index_ = 0;
    glm::vec3 centre_{0.0f};
    float amplitude_ = 0.0f;
    uint32_t step_ = 0;
    std::string name_;
};

// The viewer can set an object moving at any time (Action::ToggleMoving), so its scenes keep instances movable.
SceneOptions movable(SceneOptions options) {
    options.moving_instances = true;
    return options;
}

class ViewSession {
public:
    explicit ViewSession(const ViewOptions& options)
        : options_(options),
          settings_(options.settings),
          mode_(viewer::parse_display_mode(options.display)),
          script_(viewer::parse_key_script(options.keys)),
          window_(viewer::open_window("Prism", int(settings_.width), int(settings_.height), !options.no_vsync,
                                       options.headless)),
          loaded_(load_and_build(movable(options.scene), options.backend)),
          controls_(loaded_.scene.camera),
          moving_(loaded_) {
        // Only the interop modes tell the backend about the GL context: with host-copy (and none) it is created
        // exactly as `prism render` creates it.
        if (mode_ == viewer::DisplayMode::Auto || mode_ == viewer::DisplayMode::Interop)
            gl_ = window_->gl_context_handles();
        device_ = &device_for(options.backend);
        engine_ = make_engine(options.backend, *device_);
        display_ = make_display(*engine_);
        ablate_ = ablation(display_->path());
        BackendInfo info = engine_->info();
        std::printf("prism view: %s (%zu triangles, %zu instances) on %s [%s]\n", options.scene.scene.c_str(),
                    loaded_.device.traced_triangles, loaded_.device.instances.size(), info.name.c_str(),
                    info.device.c_str());
        std::printf("  %s %dx%d, %s\n", options.headless ? "offscreen" : "window", window_->framebuffer_width(),
                    window_->framebuffer_height(), window_->context_description().c_str());
        std::printf("  %s\n", display_->path().describe().c_str());
        std::fflush(stdout);
    }

    void run() {
        auto last_present = std::chrono::steady_clock::now();
        started_ = last_present;
        size_t next_key = 0;
        for (uint32_t frame = 0; options_.frames == 0 || frame < options_.frames; ++frame) {
            if (window_->should_close()) break;
            if (options_.seconds > 0.0 &&
                std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() >= options_.seconds)
                break;
            viewer::Input input = window_->poll();
            auto now = std::chrono::steady_clock::now();
            float seconds = std::chrono::duration<float>(now - last_present).count();
            while (next_key < script_.size() && script_[next_key].frame <= frame)
                input.actions.push_back(script_[next_key++].action);
            bool screenshot = false;
            for (Action action : input.actions) {
                if (action == Action::Quit) return finish();
                screenshot |= action == Action::Screenshot;
                apply(action);
            }
            controls_.orbit(0.005f * input.drag.x, 0.005f * input.drag.y);
            controls_.zoom(input.scroll);
            if (input.fly != glm::vec3(0.0f)) controls_.fly(input.fly * std::min(seconds, 0.1f) * 0.5f);
            if (moving_on_) engine_->update_instances(*device_, moving_.advance(), false);

            using Clock = std::chrono::steady_clock;
            auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
            bool last = options_.frames != 0 && frame + 1 == options_.frames;
            viewer::FrameTiming timing;
            // --alternate-display: blocks of frames shown and only rendered, measuring within one run what showing
            // adds (the last frame is always shown, for --screenshot, and left out of the comparison).
            bool hidden_block = options_.alternate != 0 && (frame / options_.alternate) % 2 == 1;
            if (options_.alternate != 0 && !(last && hidden_block)) {
                timing.block = hidden_block ? viewer::FrameTiming::Block::Hidden : viewer::FrameTiming::Block::Shown;
                timing.first_of_block = frame % options_.alternate == 0;
            }
            bool shows = display_->path().kind != viewer::DisplayPath::Kind::None && (!hidden_block || last);
            viewer::set_read_back(display_->path(), settings_, shows);
            if (ablate_ == "gl") settings_.copy_to_gl = false;   // GL shows the shared buffer as it is
            if (ablate_ == "copy") shows = false;                  // the frame copies, GL does nothing
            auto start = Clock::now();
            last_frame_ = engine_->render(controls_.camera(), settings_);
            auto rendered = Clock::now();
            timing.render_ms = ms(rendered - start);
            if (shows) {
                // GL runs the display asynchronously, as a viewer should: its GPU time comes from a timer query a
                // few frames later (a glFinish here would add its own latency to every frame).
                gl_timer_.begin(stats_.frames());
                display_->update(last_frame_);
                display_->draw(window_->framebuffer_width(), window_->framebuffer_height());
                gl_timer_.end();
                for (auto [index, ms] : gl_timer_.collect(false)) stats_.set_gpu_display(index, ms);
            }
            auto drawn = Clock::now();
            if (screenshot) save_screenshot(screenshot_path(frame));
            if (last && !options_.screenshot.empty()) save_screenshot(options_.screenshot);
            auto swap_start = Clock::now();
            if (shows) window_->swap();

            now = Clock::now();
            timing.display_ms = ms(drawn - rendered);   // a screenshot's read-back is in neither
            timing.present_ms = ms(now - swap_start);
            timing.frame_ms = ms(now - last_present);
            stats_.add(timing);
            double frame_seconds = std::chrono::duration<double>(now - last_present).count();
            last_present = now;
            fps_ = fps_ == 0.0 ? 1.0 / frame_seconds : 0.9 * fps_ + 0.1 / frame_seconds;
            window_->set_title(hud());
            ++frames_rendered_;
        }
        finish();
    }

private:
    // PRISM_VIEW_ABLATE (bench/view_gpu.sh) splits what showing a frame through interop costs in two: "copy" — shown
    // frames copy into the shared buffer and GL does nothing; "gl" — GL shows the shared buffer and the frame copies
    // nothing into it (the image stays the first one). Not with shared semaphores, which pair every copy with a GL
    // wait. Empty when unset.
    static std::string ablation(const viewer::DisplayPath& path) {
        const char* value = std::getenv("PRISM_VIEW_ABLATE");
        std::string ablate = value ? value : "";
        if (ablate.empty()) return ablate;
        if (ablate != "copy" && ablate != "gl")
            throw Error("view: PRISM_VIEW_ABLATE='" + ablate + "' is not one of copy, gl");
        if (path.kind != viewer::DisplayPath::Kind::Interop || path.detail.rfind("shared semaphores", 0) == 0)
            throw Error("view: PRISM_VIEW_ABLATE needs an interop display without shared semaphores (this one: " +
                        path.describe() + ")");
        return ablate;
    }

    // Whatever ends the session (--frames, Esc, the window closing): the last frame, the timing summary, --stats.
    void finish() {
        if (options_.frames != 0 || options_.seconds > 0.0) {
            double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
            std::printf("  rendered %u frames in %.1f s\n", frames_rendered_, elapsed);
        }
        for (auto [index, ms] : gl_timer_.collect(true)) stats_.set_gpu_display(index, ms);
        if ((options_.frames != 0 || options_.seconds > 0.0) && stats_.frames() != 0)
            std::printf("  last frame (%s):\n%s", hud().c_str(), frame_summary(last_frame_, settings_).c_str());
        if (stats_.frames() != 0)
            std::printf("  %s; %s\n", stats_.summary_line().c_str(), display_->path().describe().c_str());
        if (!options_.stats.empty()) write_stats();
        std::fflush(stdout);
    }

    // The device scene in the BVH layout --bvh-layout gives `spec` (auto: wide on cpu, stack on GPUs): a backend
    // switch that needs another layout builds it once from the loaded scene.
    DeviceScene& device_for(const std::string& spec) {
        BvhLayout layout = resolve_bvh_layout(options_.scene.layout, spec);
        if (layout == loaded_.device.bvh_options.layout) return loaded_.device;
        auto found = other_layouts_.find(layout);
        if (found == other_layouts_.end()) {
            std::printf("  building the %s BVH for %s\n", bvh_layout_name(layout).c_str(), spec.c_str());
            std::fflush(stdout);
            found = other_layouts_.emplace(layout, build_device_scene_for(loaded_.scene, movable(options_.scene), layout)).first;
        }
        return found->second;
    }

    std::unique_ptr<RenderEngine> make_engine(const std::string& spec, const DeviceScene& device) {
        return std::make_unique<RenderEngine>(spec, device, gl_ ? &*gl_ : nullptr);
    }

    // The display path for `engine` and the read-back it needs. Throws prism::Error with --display interop when
    // the engine has no interop (or it fails to set up).
    std::unique_ptr<viewer::FrameDisplay> make_display(RenderEngine& engine) {
        GlInteropOffer offer = engine.gl_interop();
        viewer::DisplayPath path = viewer::choose_display_path(mode_, engine.info(), offer);
        auto display = viewer::open_frame_display(mode_, path, offer.interop, settings_.width, settings_.height);
        viewer::set_read_back(display->path(), settings_);
        return display;
    }

    void write_stats() {
        BackendInfo info = engine_->info();
        const viewer::DisplayPath& path = display_->path();
        nlohmann::json json = stats_.json();
        json["tool"] = "prism view";
        json["commit"] = build_commit();
        json["scene"] = options_.scene.scene;
        json["width"] = settings_.width;
        json["height"] = settings_.height;
        json["max_depth"] = settings_.max_depth;
        json["vsync"] = !options_.no_vsync;
        json["backend"] = {{"name", info.name}, {"device", info.device}, {"driver", info.driver},
                           {"api_version", info.api_version}};
        json["backend_switches"] = backend_switches_;
        json["gl"] = window_->context_description();
        json["headless"] = options_.headless;
        json["ablate"] = ablate_.empty() ? nlohmann::json() : nlohmann::json(ablate_);
        json["display"] = {{"requested", viewer::display_mode_name(mode_)},
                           {"path", path.kind_name()},
                           {"name", path.name},
                           {"detail", path.detail},
                           {"hud", path.describe()}};
        write_file_atomically(options_.stats, json.dump(2) + "\n");
        std::printf("  wrote %s (timing summary)\n", options_.stats.c_str());
    }

    void apply(Action action) {
        const float step = 0.05f;   // scripted fly keys: 5% of the eye-target distance per press
        switch (action) {
        case Action::DepthUp: settings_.max_depth = std::min(settings_.max_depth + 1, 32u); say_depth(); break;
        case Action::DepthDown: settings_.max_depth = std::max(settings_.max_depth - 1, 1u); say_depth(); break;
        case Action::ResetCamera: controls_.reset(); break;
        case Action::ToggleMoving:
            if (moving_.empty()) break;
            moving_on_ = !moving_on_;
            std::printf("  moving object '%s': %s\n", moving_.name().c_str(), moving_on_ ? "on" : "off");
            break;
        case Action::FlyForward: controls_.fly({0.0f, 0.0f, step}); break;
        case Action::FlyBack: controls_.fly({0.0f, 0.0f, -step}); break;
        case Action::FlyLeft: controls_.fly({-step, 0.0f, 0.0f}); break;
        case Action::FlyRight: controls_.fly({step, 0.0f, 0.0f}); break;
        case Action::FlyDown: controls_.fly({0.0f, -step, 0.0f}); break;
        case Action::FlyUp: controls_.fly({0.0f, step, 0.0f}); break;
        default:
            if (viewer::is_backend_key(action)) switch_backend(viewer::backend_for_key(action));
            break;
        }
        std::fflush(stdout);
    }

    void say_depth() { std::printf("  depth %u\n", settings_.max_depth); }

    // Keeps the device the user named on the command line when the key selects the same API (4 after
    // --backend opencl:pocl stays on PoCL).
    void switch_backend(const std::string& api) {
        std::string spec = api;
        if (parse_backend_spec(options_.backend).api == api) spec = options_.backend;
        std::string current = engine_->info().name;
        if (current == api) return;
        RenderSettings previous = settings_;
        try {
            DeviceScene& next_device = device_for(spec);
            auto next = make_engine(spec, next_device);
            auto next_display = make_display(*next);
            // The old display goes first: it may hold the old backend's shared buffer.
            display_ = std::move(next_display);
            engine_ = std::move(next);
            device_ = &next_device;
        } catch (const Error& e) {
            settings_ = previous;   // make_display set the read-back for a display that is not used
            std::printf("  backend %s unavailable (%s); keeping %s\n", api.c_str(), e.what(), current.c_str());
            return;
        }
        ++backend_switches_;
        BackendInfo info = engine_->info();
        std::printf("  switched to %s [%s], %s\n", info.name.c_str(), info.device.c_str(),
                    display_->path().describe().c_str());
    }

    std::string screenshot_path(uint32_t frame) const {
        if (!options_.screenshot.empty()) return options_.screenshot;
        return "prism-view-" + std::to_string(frame) + ".png";
    }

    void save_screenshot(const std::string& path) {
        if (display_->path().kind == viewer::DisplayPath::Kind::None) {
            std::printf("  no screenshot: --display none shows nothing\n");
            return;
        }
        std::vector<uint32_t> pixels = window_->read_pixels();
        write_png(path, window_->framebuffer_width(), window_->framebuffer_height(), pixels);
        std::printf("  wrote %s (window read-back, %dx%d)\n", path.c_str(), window_->framebuffer_width(),
                    window_->framebuffer_height());
        std::fflush(stdout);
    }

    // The window title is the HUD: backend and device, fps, ms per stage, Mrays/s, display path.
    std::string hud() const {
        BackendInfo info = engine_->info();
        const FrameStats& stats = last_frame_.stats;
        StageTotals totals = stage_totals(stats);
        std::string text = "Prism - " + info.name + " [" + info.device + "]";
        char part[256];
        std::snprintf(part, sizeof part, " | %.1f fps | frame %.1f ms:", fps_, stats.frame_ms);
        text += part;
        for (size_t i = 0; i < stage_count; ++i) {
            std::snprintf(part, sizeof part, " %s %.1f", stage_name(Stage(i)), totals.by_stage[i]);
            text += part;
        }
        double mrays = stats.frame_ms > 0.0 ? double(stats.total_rays()) / (stats.frame_ms * 1e3) : 0.0;
        std::snprintf(part, sizeof part, " | %.1f Mrays/s | depth %u | %s", mrays, settings_.max_depth,
                      display_->path().describe().c_str());
        return text + part;
    }

    ViewOptions options_;
    RenderSettings settings_;
    viewer::DisplayMode mode_;
    std::vector<viewer::ScriptedKey> script_;
    std::unique_ptr<viewer::Window> window_;   // first: no display fails fast, and the GL context outlives
                                               // the FrameDisplay
    std::optional<GlContextHandles> gl_;   // given to backends in the interop modes
    LoadedScene loaded_;
    std::map<BvhLayout, DeviceScene> other_layouts_;   // built on a backend switch that needs another layout;
                                                       // before engine_, which traces one of them
    DeviceScene* device_ = nullptr;                     // the scene the current engine traces
    viewer::CameraControls controls_;
    MovingObject moving_;
    bool moving_on_ = false;
    std::unique_ptr<RenderEngine> engine_;
    std::unique_ptr<viewer::FrameDisplay> display_;
    FrameResult last_frame_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();   // the first frame
    uint32_t frames_rendered_ = 0;
    double fps_ = 0.0;
    viewer::FrameTimings stats_;
    viewer::GlTimer gl_timer_;
    int backend_switches_ = 0;
    std::string ablate_;   // PRISM_VIEW_ABLATE: "", "copy" or "gl"
};

void run_view(const ViewOptions& options) {
    if (options.frames == 0 && !options.screenshot.empty())
        throw Error("view: --screenshot needs --frames (P saves screenshots in an interactive session)");
    if (!options.screenshot.empty()) check_output_extension(options.screenshot);
    if (!options.screenshot.empty() && viewer::parse_display_mode(options.display) == viewer::DisplayMode::None)
        throw Error("view: --screenshot needs a display (--display none shows nothing)");
    ViewSession session(options);
    session.run();
}

#else

void run_view(const ViewOptions&) {
    throw Error("view: not available in this build (GLFW or OpenGL not found at configure time: "
                "apt-get install libglfw3-dev libgl-dev and reconfigure)");
}

#endif

}  // namespace

void add_view_command(CLI::App& app) {
    auto options = std::make_shared<ViewOptions>();
    auto* command = app.add_subcommand("view", "Interactive preview in a window (GLFW + OpenGL)");
    add_scene_options(command, options->scene);
    command->add_option("--backend", options->backend,
                        "auto, cpu-ref, cpu, cuda, opencl, vulkan; a device after a colon (opencl:pocl)")
        ->capture_default_str();
    command->add_option("--width", options->settings.width, "window and frame width")->capture_default_str();
    command->add_option("--height", options->settings.height, "window and frame height")->capture_default_str();
    command->add_option("--depth", options->settings.max_depth, "ray generations traced (+/- change it)")
        ->capture_default_str();
    command->add_option("--frames", options->frames, "render this many frames and exit (0: until Esc)")
        ->capture_default_str();
    command->add_option("--seconds", options->seconds,
                        "stop after this many seconds of wall-clock time (0: no limit; with --frames, whichever ends first)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--screenshot", options->screenshot,
                        "with --frames: save the last frame as read back from the window (.png)");
    command->add_flag("--no-vsync", options->no_vsync, "present without waiting for vertical sync");
    command->add_option("--keys", options->keys,
                        "scripted key presses FRAME:KEY,... (keys 1-5 + - P R M Esc W A S D Q E), e.g. 0:M,3:2");
    command->add_option("--display", options->display,
                        "how frames reach the window: auto (GPU buffer interop where the backend and GL allow it, "
                        "else host copy), interop (required), host-copy, none (render only)")
        ->capture_default_str();
    command->add_option("--stats", options->stats,
                        "write the timing summary (median render/display/frame ms, fps, display path) as JSON");
    command->add_option("--alternate-display", options->alternate,
                        "measure what showing a frame costs within one run: N frames shown, then N only rendered, and "
                        "so on; the summary and --stats compare their median frame times (0: show every frame)")
        ->capture_default_str();
    command->add_flag("--headless", options->headless,
                      "draw into an offscreen framebuffer of an EGL context (an EGL device, else Mesa's surfaceless "
                      "platform) instead of a window: no X server needed; input only from --keys");
    command->callback([options] {
        route_output();
        if (options->headless && options->frames == 0 && options->seconds <= 0.0)
            throw Error("view: --headless needs --frames or --seconds (there is no window to close)");
        run_view(*options);
    });
}

}  // namespace prism::app
