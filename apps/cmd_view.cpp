// `prism view`: the interactive preview. This file drives it — scene, RenderEngine, backend switching, dropped
// files, the moving object, when to render (only when something changed; smaller while moving) — and viewer/ does
// the window, input, camera controls, panel and display. Without GLFW/OpenGL at configure time
// the command still exists and says why it cannot run.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/display_options.h"
#include "apps/frame_report.h"
#include "apps/option_checks.h"
#include "apps/scene_options.h"
#include "core/util/build_info.h"
#include "core/util/environment.h"
#include "core/util/error.h"
#include "core/image/image_io.h"
#include "core/util/output_file.h"
#include "core/render/render_engine.h"
#include "core/scene/scene_motion.h"

#ifdef PRISM_HAVE_VIEWER
#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>

#include "core/loaders/environment_maps.h"
#include "viewer/backend_check.h"
#include "viewer/camera_controls.h"
#include "viewer/frame_display.h"
#include "viewer/frame_timing.h"
#include "viewer/gl_timer.h"
#include "viewer/held_keys.h"
#include "viewer/interactive_scale.h"
#include "viewer/key_script.h"
#include "viewer/panel.h"
#include "viewer/scene_bounds.h"
#include "viewer/screenshot_names.h"
#include "viewer/window.h"
#endif

namespace prism::app {
namespace {

struct ViewOptions {
    SceneOptions scene;
    std::string backend = "auto";
    RenderSettings settings;
    uint32_t frames = 0;     // 0: until Esc or the window closes
    double seconds = 0.0;    // > 0: also stop after this much wall-clock time (bench/soak_viewer.sh)
    std::string screenshot;  // with --frames: the last frame, read back from the window
    bool no_vsync = false;
    std::string keys;              // scripted key presses, "FRAME:KEY,..."
    std::string display = "auto";  // auto, interop, host-copy, none (viewer/frame_display.h)
    std::string stats;             // --stats: the timing summary as JSON
    bool headless = false;         // an offscreen EGL framebuffer instead of a window (viewer/offscreen_window.h)
    uint32_t alternate = 0;        // --alternate-display N: N frames shown, N only rendered, ... (0: every frame shown)
    bool no_panel = false;         // --no-panel, or PRISM_VIEW_PANEL=0: the frame alone, as before the panel
    std::string interactive_scale = "auto";  // resolution while moving: auto (from --target-fps) or a fraction
    double target_fps = 30.0;
    std::vector<std::string> drops;  // --drop FRAME:PATH: scripted file drops
};

#ifdef PRISM_HAVE_VIEWER

using viewer::Action;

// What M sets moving. A scene with motion of its own (a glTF animation, a scene file's spins) plays it
// (core/scene/scene_motion.h); any other scene gets one instance turning about its own vertical axis and swinging
// left and right. The swing is advanced per frame (not per second) and a headless run plays the scene's motion at
// a fixed step, so scripted runs are reproducible. RenderEngine refits the top level (and the BVHs of the meshes an
// animation deforms).
class MovingObject {
public:
    static constexpr double kScriptedStep = 1.0 / 30.0;  // seconds of the scene's motion per headless frame

    explicit MovingObject(const LoadedScene& loaded) {
        for (const Instance& instance : loaded.scene.instances) base_.push_back(instance.transform);
        if (base_.empty()) return;
        if (scene_moves(loaded.scene)) {
            const NodeAnimation& animation = loaded.scene.animation;
            name_ = animation.plays() ? "animation '" + animation.name + "'" : "spinning objects";
            plays_scene_ = true;
            return;
        }
        index_ = base_.size() - 1;  // the loaders and builtin scenes add the floor first and the model last
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
    // What M just did, for the terminal: "moving object 'NAME': on", "animation 'NAME': playing", ...
    std::string status(bool on) const {
        if (plays_scene_) return name_ + (on ? ": playing" : ": paused");
        return "moving object '" + name_ + (on ? "': on" : "': off");
    }

    // Moves `loaded` (the scene this object was made from, and the `device` scene the engine traces) `seconds` of
    // the scene's motion on (the swing ignores it: one step per call).
    void advance(double seconds, RenderEngine& engine, const LoadedScene& loaded, DeviceScene& device) {
        ++step_;
        if (plays_scene_) {
            played_ += seconds;
            engine.move_to(loaded.scene, device, played_);
            return;
        }
        float angle = 0.15f * float(step_);
        glm::vec3 offset{amplitude_ * std::sin(angle), 0.0f, 0.0f};
        std::vector<glm::mat4> transforms = base_;
        transforms[index_] = glm::translate(glm::mat4(1.0f), centre_ + offset) *
                             glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0.0f, 1.0f, 0.0f)) *
                             glm::translate(glm::mat4(1.0f), -centre_) * base_[index_];
        engine.update_instances(device, transforms, false);
    }

private:
    std::vector<glm::mat4> base_;
    bool plays_scene_ = false;  // the scene has motion of its own: its animation and spins
    double played_ = 0.0;
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

// A dropped (or reloaded) file: a scene, or an environment map for the current scene.
enum class DroppedKind { Scene, Environment };

// Which kind `path` is, by its name (or "builtin:...") (a cube map is a folder of six faces, or one face inside one);
// throws prism::Error naming the file when it is neither.
DroppedKind classify_dropped(const std::filesystem::path& path) {
    if (path.string().rfind("builtin:", 0) == 0) return DroppedKind::Scene;  // L on a builtin scene
    std::string name = path.filename().string();
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    auto ends_with = [&](const char* suffix) {
        std::string s = suffix;
        return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
    };
    for (const char* suffix : {".gltf", ".glb", ".obj", ".ply", ".ply.gz", ".json"})
        if (ends_with(suffix)) return DroppedKind::Scene;
    if (ends_with(".hdr")) return DroppedKind::Environment;
    std::error_code error;
    if (std::filesystem::is_directory(path, error) && is_cube_map_folder(path)) return DroppedKind::Environment;
    if (is_cube_map_folder(path.parent_path())) return DroppedKind::Environment;
    throw Error(path.string() +
                ": not a scene (.gltf .glb .obj .ply .ply.gz .json) nor an environment map (.hdr, "
                "a cube-map folder)");
}

// Loads an environment map into `scene` (replacing its environment).
void load_environment(const std::filesystem::path& path, Scene& scene) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) return load_cube_map(path, scene);
    std::string name = path.filename().string();
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".hdr") == 0) return load_equirect_map(path, scene);
    load_cube_map(path.parent_path(), scene);  // a face of a cube map: the folder it is in
}

class ViewSession {
public:
    explicit ViewSession(const ViewOptions& options)
        : options_(options),
          settings_(options.settings),
          mode_(viewer::parse_display_mode(options.display)),
          script_(viewer::parse_key_script(options.keys)),
          drops_(parse_drops(options.drops)),
          scale_(options.interactive_scale, options.target_fps),
          window_(viewer::open_window("Prism", int(settings_.width), int(settings_.height), !options.no_vsync,
                                      options.headless)),
          loaded_(std::make_unique<LoadedScene>(load_and_build(movable(options.scene), options.backend))),
          controls_(loaded_->scene.camera),
          moving_(*loaded_),
          scene_file_(options.scene.scene) {
        // Only the interop modes tell the backend about the GL context: with host-copy (and none) it is created
        // exactly as `prism render` creates it.
        if (mode_ == viewer::DisplayMode::Auto || mode_ == viewer::DisplayMode::Interop)
            gl_ = window_->gl_context_handles();
        full_width_ = settings_.width;
        full_height_ = settings_.height;
        controls_.set_scene_bounds(viewer::world_bounds(loaded_->scene));
        backend_spec_ = options.backend;
        device_ = &device_for(options.backend);
        engine_ = make_engine(options.backend, *device_);
        display_ = make_display(*engine_);
        ablate_ = ablation(display_->path());
        if (!options.no_panel) {
            // The panel is a help, not the point: without it (its GL loader finds no libGL.so.1) the frames still
            // show, and the console and --stats say why it is missing.
            try {
                panel_ = std::make_unique<viewer::Panel>(*window_);
            } catch (const Error& e) {
                panel_error_ = e.what();
            }
        }
        BackendInfo info = engine_->info();
        std::printf("prism view: %s (%zu triangles, %zu instances) on %s [%s]\n", options.scene.scene.c_str(),
                    loaded_->device.traced_triangles, loaded_->device.instances.size(), info.name.c_str(),
                    info.device.c_str());
        std::printf("  %s %dx%d, %s\n", options.headless ? "offscreen" : "window", window_->framebuffer_width(),
                    window_->framebuffer_height(), window_->context_description().c_str());
        std::printf("  %s\n", display_->path().describe().c_str());
        if (!panel_error_.empty()) std::printf("  no panel: %s\n", panel_error_.c_str());
        std::fflush(stdout);
        update_title();
    }

    void run() {
        using Clock = std::chrono::steady_clock;
        started_ = Clock::now();
        auto last_present = started_;
        // --frames N renders a frame on every pass (benchmarks, scripted runs); otherwise the session renders only
        // when something changed, and waits for events in between.
        const bool continuous = options_.frames != 0;
        bool counted_interval = false;  // last_present ends an interval fps may use (not an idle wait)
        for (;;) {
            if (window_->should_close()) break;
            double elapsed = std::chrono::duration<double>(Clock::now() - started_).count();
            if (options_.seconds > 0.0 && elapsed >= options_.seconds) break;
            if (continuous && frames_rendered_ >= options_.frames) break;
            const uint32_t frame = frames_rendered_;

            // Scripted drops go through the window as a real drop does (Window::receive_drop).
            while (next_drop_ < drops_.size() && drops_[next_drop_].first <= frame)
                window_->receive_drop({drops_[next_drop_++].second});
            bool script_left = next_key_ < script_.size() || next_drop_ < drops_.size();
            bool busy =
                continuous || need_render_ || last_render_scaled_ || moving_on_ || held_keys_.any_down() || script_left;
            viewer::Input input;
            if (busy) {
                input = window_->poll();
            } else {
                double timeout = options_.seconds > 0.0 ? options_.seconds - elapsed : 60.0;
                input = window_->wait(std::max(timeout, 0.001));
                counted_interval = false;  // the time spent waiting is not a frame interval
            }
            const double now = viewer::input_clock();
            for (const viewer::FlyKeyEvent& event : input.fly_keys) {
                if (event.pressed)
                    held_keys_.press(event.key, event.time);
                else
                    held_keys_.release(event.key, event.time);
            }
            // A scripted fly key is held for its time, ending now: the same presses and releases as the window's.
            while (next_key_ < script_.size() && script_[next_key_].frame <= frame) {
                const viewer::ScriptedKey& key = script_[next_key_++];
                viewer::FlyKey fly;
                if (viewer::fly_key_for(key.action, &fly)) {
                    held_keys_.press(fly, now - key.hold_seconds);
                    held_keys_.release(fly, now);
                } else {
                    input.actions.push_back(key.action);
                }
            }

            bool screenshot = false;
            bool redraw = input.resized || (panel_ && input.any());
            for (Action action : input.actions) {
                if (action == Action::Quit) return finish();
                if (action == Action::Screenshot)
                    screenshot = true;
                else
                    need_render_ |= apply(action);
                redraw = true;
            }
            for (const std::string& path : input.dropped) need_render_ |= load_file(path, true);
            if (input.resized && !options_.headless) {
                full_width_ = uint32_t(std::max(window_->framebuffer_width(), 1));
                full_height_ = uint32_t(std::max(window_->framebuffer_height(), 1));
                need_render_ = true;
            }
            bool moving = false;
            if (input.drag != glm::vec2(0.0f)) {
                controls_.orbit(0.005f * input.drag.x, 0.005f * input.drag.y);
                moving = true;
            }
            if (input.pan != glm::vec2(0.0f)) {
                controls_.pan(input.pan, window_->framebuffer_height());
                moving = true;
            }
            if (input.scroll != 0.0f) {
                controls_.zoom(input.scroll);
                moving = true;
            }
            glm::vec3 held = held_keys_.collect(now);
            if (held != glm::vec3(0.0f)) {
                controls_.fly_for(held);
                moving = true;
            }
            if (moving_on_) {
                // Real time in a window (a stalled frame counts at most a tenth of a second), a fixed step headless.
                double step =
                    options_.headless ? MovingObject::kScriptedStep : std::clamp(now - motion_clock_, 0.0, 0.1);
                moving_.advance(step, *engine_, *loaded_, *device_);
                moving = true;
            }
            motion_clock_ = now;
            moving |= held_keys_.any_down();

            bool render = continuous || moving || need_render_ || last_render_scaled_;
            if (!render && !redraw && !screenshot) continue;  // nothing changed: back to waiting

            viewer::FrameTiming timing;
            auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
            bool last = continuous && frame + 1 == options_.frames;
            bool shows = display_->path().kind != viewer::DisplayPath::Kind::None;
            auto start = Clock::now();
            if (render) {
                // --alternate-display: blocks of frames shown and only rendered, measuring within one run what
                // showing adds (the last frame is always shown, for --screenshot, and left out of the comparison).
                bool hidden_block = options_.alternate != 0 && (frame / options_.alternate) % 2 == 1;
                if (options_.alternate != 0 && !(last && hidden_block)) {
                    timing.block =
                        hidden_block ? viewer::FrameTiming::Block::Hidden : viewer::FrameTiming::Block::Shown;
                    timing.first_of_block = frame % options_.alternate == 0;
                }
                shows = shows && (!hidden_block || last);
                double scale = moving ? scale_.moving_scale() : 1.0;
                resize_render(scale);
                viewer::set_read_back(display_->path(), settings_, shows);
                if (ablate_ == "gl") settings_.copy_to_gl = false;  // GL shows the shared buffer as it is
                if (ablate_ == "copy") shows = false;               // the frame copies, GL does nothing
                start = Clock::now();
                last_frame_ = engine_->render(controls_.camera(), settings_);
                scale_.record(settings_.width, settings_.height, last_frame_.stats.frame_ms);
                last_render_scaled_ = settings_.width != full_width_ || settings_.height != full_height_;
                need_render_ = false;
                ++frames_rendered_;
            }
            auto rendered = Clock::now();
            if (shows) {
                // GL runs the display asynchronously, as a viewer should: its GPU time comes from a timer query a
                // few frames later (a glFinish here would add its own latency to every frame).
                if (render) gl_timer_.begin(stats_.frames());
                if (render) display_->update(last_frame_);
                display_->draw(window_->framebuffer_width(), window_->framebuffer_height());
                if (panel_) apply(panel_->draw(panel_view(moving), help_));
                if (render) {
                    gl_timer_.end();
                    for (auto [index, gpu_ms] : gl_timer_.collect(false)) stats_.set_gpu_display(index, gpu_ms);
                }
            }
            auto drawn = Clock::now();
            if (screenshot) save_screenshot(interactive_screenshot_path());
            if (last && !options_.screenshot.empty()) save_screenshot(options_.screenshot);
            auto swap_start = Clock::now();
            if (shows) {
                window_->swap();
                ++frames_shown_;
            }
            auto presented = Clock::now();
            if (!render) continue;  // the panel drawn again over the same frame: no frame timing
            timing.render_ms = ms(rendered - start);
            timing.display_ms = ms(drawn - rendered);  // a screenshot's read-back is in neither
            timing.present_ms = ms(presented - swap_start);
            timing.frame_ms = ms(presented - last_present);
            stats_.add(timing);
            if (counted_interval) {
                double interval_ms = timing.frame_ms;
                frame_interval_ms_ =
                    frame_interval_ms_ == 0.0 ? interval_ms : 0.9 * frame_interval_ms_ + 0.1 * interval_ms;
            }
            last_present = presented;
            counted_interval = true;
        }
        finish();
    }

private:
    static std::vector<std::pair<uint32_t, std::string>> parse_drops(const std::vector<std::string>& items) {
        std::vector<std::pair<uint32_t, std::string>> drops;
        for (const std::string& item : items) {
            size_t colon = item.find(':');
            std::string frame = colon == std::string::npos ? "" : item.substr(0, colon);
            if (frame.empty() || frame.size() > 9 || colon + 1 >= item.size() ||
                !std::all_of(frame.begin(), frame.end(),
                             [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
                throw Error("view: --drop expects FRAME:PATH, got '" + item + "'");
            drops.emplace_back(uint32_t(std::stoul(frame)), item.substr(colon + 1));
        }
        std::stable_sort(drops.begin(), drops.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        return drops;
    }

    // PRISM_VIEW_ABLATE (bench/view_gpu.sh) splits what showing a frame through interop costs in two: "copy" — shown
    // frames copy into the shared buffer and GL does nothing; "gl" — GL shows the shared buffer and the frame copies
    // nothing into it (the image stays the first one). Not with shared semaphores, which pair every copy with a GL
    // wait. Empty when unset.
    static std::string ablation(const viewer::DisplayPath& path) {
        std::string ablate = setting_choice(Setting::ViewAblate, {"copy", "gl"}, "view");
        if (ablate.empty()) return ablate;
        if (path.kind != viewer::DisplayPath::Kind::Interop || path.detail.rfind("shared semaphores", 0) == 0)
            throw Error("view: PRISM_VIEW_ABLATE needs an interop display without shared semaphores (this one: " +
                        path.describe() + ")");
        return ablate;
    }

    // Whatever ends the session (--frames, Esc, the window closing): the last frame, the timing summary, --stats.
    void finish() {
        if (options_.frames != 0 || options_.seconds > 0.0) {
            double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
            std::printf("  rendered %u frames in %.1f s (%llu shown)\n", frames_rendered_, elapsed,
                        static_cast<unsigned long long>(frames_shown_));
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
        if (layout == loaded_->device.bvh_options.layout) return loaded_->device;
        auto found = other_layouts_.find(layout);
        if (found == other_layouts_.end()) {
            std::printf("  building the %s BVH for %s\n", bvh_layout_name(layout).c_str(), spec.c_str());
            std::fflush(stdout);
            found =
                other_layouts_.emplace(layout, build_device_scene_for(loaded_->scene, movable(options_.scene), layout))
                    .first;
        }
        return found->second;
    }

    std::unique_ptr<RenderEngine> make_engine(const std::string& spec, const DeviceScene& device) {
        return std::make_unique<RenderEngine>(spec, device, gl_ ? &*gl_ : nullptr);
    }

    // The display path for `engine` and the read-back it needs, for frames of the current render size. Throws
    // prism::Error with --display interop when the engine has no interop (or it fails to set up).
    std::unique_ptr<viewer::FrameDisplay> make_display(RenderEngine& engine) {
        GlInteropOffer offer = engine.gl_interop();
        viewer::DisplayPath path = viewer::choose_display_path(mode_, engine.info(), offer);
        auto display = viewer::open_frame_display(mode_, path, offer.interop, settings_.width, settings_.height);
        viewer::set_read_back(display->path(), settings_);
        display_width_ = settings_.width;
        display_height_ = settings_.height;
        return display;
    }

    // Renders the next frame at `scale` of the window's size; an interop display is made again for a new size
    // (its shared buffer holds exactly one frame).
    void resize_render(double scale) {
        settings_.width = viewer::InteractiveScale::scaled(full_width_, scale);
        settings_.height = viewer::InteractiveScale::scaled(full_height_, scale);
        if (settings_.width == display_width_ && settings_.height == display_height_) return;
        if (display_->path().kind != viewer::DisplayPath::Kind::Interop) {
            display_width_ = settings_.width;
            display_height_ = settings_.height;
            return;
        }
        display_.reset();  // it holds the shared buffer of the old size
        display_ = make_display(*engine_);
    }

    void write_stats() {
        BackendInfo info = engine_->info();
        const viewer::DisplayPath& path = display_->path();
        nlohmann::json json = stats_.json();
        json["tool"] = "prism view";
        json["commit"] = build_commit();
        json["scene"] = scene_file_;
        json["width"] = settings_.width;
        json["height"] = settings_.height;
        json["window"] = {{"width", full_width_}, {"height", full_height_}};
        json["max_depth"] = settings_.max_depth;
        json["vsync"] = !options_.no_vsync;
        json["backend"] = {
            {"name", info.name}, {"device", info.device}, {"driver", info.driver}, {"api_version", info.api_version}};
        json["backend_switches"] = backend_switches_;
        json["gl"] = window_->context_description();
        json["headless"] = options_.headless;
        json["panel"] = panel_ != nullptr;
        if (!panel_error_.empty()) json["panel_error"] = panel_error_;
        json["frames_rendered"] = frames_rendered_;
        json["frames_shown"] = frames_shown_;
        json["interactive_scale"] = {{"setting", options_.interactive_scale},
                                     {"target_fps", options_.target_fps},
                                     {"moving_scale", scale_.moving_scale()}};
        const Camera& camera = controls_.camera();
        json["camera"] = {{"position", {camera.position.x, camera.position.y, camera.position.z}},
                          {"target", {camera.target.x, camera.target.y, camera.target.z}},
                          {"fly_speed", controls_.fly_speed()}};
        json["files_loaded"] = files_loaded_;
        json["load_errors"] = load_errors_;
        json["ablate"] = ablate_.empty() ? nlohmann::json() : nlohmann::json(ablate_);
        json["display"] = {{"requested", viewer::display_mode_name(mode_)},
                           {"path", path.kind_name()},
                           {"name", path.name},
                           {"detail", path.detail},
                           {"hud", path.describe()}};
        write_file_atomically(options_.stats, json.dump(2) + "\n");
        std::printf("  wrote %s (timing summary)\n", options_.stats.c_str());
    }

    // Applies a key (or panel) action; true when the frame must be rendered again.
    bool apply(Action action) {
        bool changed = true;
        switch (action) {
            case Action::DepthUp: set_depth(std::min(settings_.max_depth + 1, 32u)); break;
            case Action::DepthDown: set_depth(std::max(settings_.max_depth - 1, 1u)); break;
            case Action::ExposureDown: set_exposure(settings_.exposure - 0.5f); break;
            case Action::ExposureUp: set_exposure(settings_.exposure + 0.5f); break;
            case Action::ToggleToneMap:
                set_tone_map(settings_.tone_map == ToneMap::None ? ToneMap::Neutral : ToneMap::None);
                break;
            case Action::ResetCamera: controls_.reset(); break;
            case Action::FrameScene:
                controls_.frame_scene(float(full_width_) / float(std::max(full_height_, 1u)));
                break;
            case Action::ToggleHelp:
                help_ = !help_;
                changed = false;
                break;
            case Action::Reload: changed = reload(); break;
            case Action::ToggleMoving:
                if (moving_.empty()) break;
                moving_on_ = !moving_on_;
                std::printf("  %s\n", moving_.status(moving_on_).c_str());
                break;
            default:
                if (viewer::is_backend_key(action)) changed = switch_backend(viewer::backend_for_key(action));
                break;
        }
        std::fflush(stdout);
        return changed;
    }

    // What the panel asked for: applied before the next frame (the loop polls again at once).
    void apply(const viewer::PanelRequest& request) {
        if (request.depth) set_depth(*request.depth);
        if (request.exposure) set_exposure(*request.exposure);
        if (request.tone_map) set_tone_map(*request.tone_map ? ToneMap::Neutral : ToneMap::None);
        if (request.backend) switch_backend(*request.backend);
        if (request.reload) reload();
        if (request.toggle_help) help_ = !help_;
        if (request.depth || request.exposure || request.tone_map || request.backend || request.reload)
            need_render_ = true;
    }

    void set_depth(uint32_t depth) {
        settings_.max_depth = std::clamp(depth, 1u, 32u);
        std::printf("  depth %u\n", settings_.max_depth);
    }

    void set_exposure(float stops) {
        settings_.exposure = std::clamp(stops, -64.0f, 64.0f);
        std::printf("  exposure %+.1f EV\n", double(settings_.exposure));
    }

    void set_tone_map(ToneMap tone_map) {
        settings_.tone_map = tone_map;
        std::printf("  tone map %s\n", tone_map == ToneMap::Neutral ? "neutral" : "none");
    }

    // Keeps the device the user named on the command line when the key selects the same API (4 after
    // --backend opencl:pocl stays on PoCL). Asks the backend's probe first, so an unavailable one costs nothing.
    bool switch_backend(const std::string& api) {
        std::string spec = api;
        if (parse_backend_spec(options_.backend).api == api) spec = options_.backend;
        std::string current = engine_->info().name;
        if (current == api) return false;
        std::string why = viewer::why_backend_unavailable(spec);
        if (why.empty()) {
            RenderSettings previous = settings_;
            try {
                DeviceScene& next_device = device_for(spec);
                auto next = make_engine(spec, next_device);
                auto next_display = make_display(*next);
                // The old display goes first: it may hold the old backend's shared buffer.
                display_ = std::move(next_display);
                engine_ = std::move(next);
                device_ = &next_device;
                backend_spec_ = spec;
            } catch (const Error& e) {
                settings_ = previous;  // make_display set the read-back for a display that is not used
                why = e.what();
            }
        }
        if (!why.empty()) {
            std::printf("  backend %s unavailable (%s); keeping %s\n", api.c_str(), why.c_str(), current.c_str());
            say("backend " + api + " unavailable: " + why, true);
            return false;
        }
        ++backend_switches_;
        BackendInfo info = engine_->info();
        std::printf("  switched to %s [%s], %s\n", info.name.c_str(), info.device.c_str(),
                    display_->path().describe().c_str());
        say("switched to " + info.name, false);
        update_title();
        return true;
    }

    // A dropped file (or L: the current one again). Errors go to the panel and the console; the session goes on
    // with what it had. True when something new was loaded.
    bool load_file(const std::string& path, bool dropped) {
        try {
            DroppedKind kind = classify_dropped(path);
            std::printf("  loading %s\n", path.c_str());
            std::fflush(stdout);
            auto next = std::make_unique<LoadedScene>();
            if (kind == DroppedKind::Scene) {
                SceneOptions scene = movable(options_.scene);
                scene.scene = path;
                *next = load_and_build(scene, backend_spec_);
                if (!environment_file_.empty() && !dropped) load_environment(environment_file_, next->scene);
            } else {
                next->scene = loaded_->scene;
                load_environment(path, next->scene);
                next->device =
                    build_device_scene_for(next->scene, movable(options_.scene), loaded_->device.bvh_options.layout);
            }
            replace_scene(std::move(next), kind == DroppedKind::Scene && dropped);
            if (kind == DroppedKind::Scene) {
                scene_file_ = path;
                if (dropped) environment_file_.clear();
            } else {
                environment_file_ = path;
            }
            ++files_loaded_;
            say("loaded " + std::filesystem::path(path).filename().string(), false);
            update_title();
            return true;
        } catch (const std::exception& e) {
            ++load_errors_;
            std::printf("  cannot load: %s\n", e.what());
            std::fflush(stdout);
            say(e.what(), true);
            return false;
        }
    }

    bool reload() {
        bool ok = load_file(scene_file_, false);
        if (ok && !environment_file_.empty()) say("reloaded " + scene_file_ + " with " + environment_file_, false);
        return ok;
    }

    // Swaps in a new scene: a new engine on it (the same backend), a new display; `new_camera`: the scene's own
    // camera (a dropped scene), else the current view is kept (an environment, a reload).
    void replace_scene(std::unique_ptr<LoadedScene> next, bool new_camera) {
        auto engine = make_engine(backend_spec_, next->device);
        auto display = make_display(*engine);
        display_ = std::move(display);
        engine_ = std::move(engine);
        other_layouts_.clear();
        loaded_ = std::move(next);
        device_ = &loaded_->device;
        if (new_camera) controls_ = viewer::CameraControls(loaded_->scene.camera);
        controls_.set_scene_bounds(viewer::world_bounds(loaded_->scene));
        moving_ = MovingObject(*loaded_);
        moving_on_ = false;
    }

    void say(const std::string& message, bool error) {
        message_ = message;
        message_is_error_ = error;
    }

    void update_title() { window_->set_title("Prism - " + scene_file_ + " - " + engine_->info().name); }

    std::string interactive_screenshot_path() const {
        if (!options_.screenshot.empty() && options_.frames != 0) return options_.screenshot;
        return viewer::next_screenshot_path().string();
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
        say("wrote " + path, false);
        std::fflush(stdout);
    }

    double mrays_per_second() const {
        const FrameStats& stats = last_frame_.stats;
        return stats.frame_ms > 0.0 ? double(stats.total_rays()) / (stats.frame_ms * 1e3) : 0.0;
    }

    viewer::PanelView panel_view(bool moving) const {
        viewer::PanelView view;
        BackendInfo info = engine_->info();
        auto name = [](const std::string& file) { return std::filesystem::path(file).filename().string(); };
        view.scene = name(scene_file_) + (environment_file_.empty() ? "" : " + " + name(environment_file_));
        view.backend = info.name;
        view.device = info.device;
        view.display_path = display_->path().describe();
        view.frame_ms = frame_interval_ms_;
        view.fps = frame_interval_ms_ > 0.0 ? 1000.0 / frame_interval_ms_ : 0.0;
        view.render_ms = last_frame_.stats.frame_ms;
        view.mrays_per_second = mrays_per_second();
        StageTotals totals = stage_totals(last_frame_.stats);
        for (size_t i = 0; i < stage_count; ++i) view.stage_ms.emplace_back(stage_name(Stage(i)), totals.by_stage[i]);
        view.render_width = last_frame_.width;
        view.render_height = last_frame_.height;
        view.window_width = full_width_;
        view.window_height = full_height_;
        view.depth = settings_.max_depth;
        view.exposure = settings_.exposure;
        view.tone_map = settings_.tone_map == ToneMap::Neutral;
        char activity[96];
        if (moving)
            std::snprintf(activity, sizeof activity, "moving (%.3g of full resolution)",
                          double(settings_.width) / double(full_width_));
        else
            std::snprintf(activity, sizeof activity, "still: full resolution, idle until a change");
        view.activity = activity;
        view.frames_rendered = frames_rendered_;
        view.frames_shown = frames_shown_ + 1;  // this one
        view.message = message_;
        view.message_is_error = message_is_error_;
        view.backends = {"cpu-ref", "cpu", "cuda", "opencl", "vulkan"};
        return view;
    }

    // The one-line summary a --frames/--seconds run ends with: backend and device, the frame's time per stage,
    // Mrays/s, depth and display path.
    std::string hud() const {
        BackendInfo info = engine_->info();
        const FrameStats& stats = last_frame_.stats;
        StageTotals totals = stage_totals(stats);
        std::string text = info.name + " [" + info.device + "]";
        char part[256];
        std::snprintf(part, sizeof part, " | render %.1f ms:", stats.frame_ms);
        text += part;
        for (size_t i = 0; i < stage_count; ++i) {
            std::snprintf(part, sizeof part, " %s %.1f", stage_name(Stage(i)), totals.by_stage[i]);
            text += part;
        }
        std::snprintf(part, sizeof part, " | %.1f Mrays/s | %ux%u | depth %u | %s", mrays_per_second(),
                      last_frame_.width, last_frame_.height, settings_.max_depth, display_->path().describe().c_str());
        return text + part;
    }

    ViewOptions options_;
    RenderSettings settings_;
    viewer::DisplayMode mode_;
    std::vector<viewer::ScriptedKey> script_;
    std::vector<std::pair<uint32_t, std::string>> drops_;  // --drop, by frame
    viewer::InteractiveScale scale_;
    std::unique_ptr<viewer::Window> window_;  // first: no display fails fast, and the GL context outlives
                                              // the FrameDisplay and the panel
    std::optional<GlContextHandles> gl_;      // given to backends in the interop modes
    std::unique_ptr<LoadedScene> loaded_;
    std::map<BvhLayout, DeviceScene> other_layouts_;  // built on a backend switch that needs another layout;
                                                      // before engine_, which traces one of them
    DeviceScene* device_ = nullptr;                   // the scene the current engine traces
    viewer::CameraControls controls_;
    MovingObject moving_;
    bool moving_on_ = false;
    double motion_clock_ = 0.0;     // input_clock() at the last frame: how far the scene's motion advances
    std::string scene_file_;        // what L reloads
    std::string environment_file_;  // a dropped environment map, kept on reload
    std::string backend_spec_;      // the current engine's, as created
    std::unique_ptr<RenderEngine> engine_;
    std::unique_ptr<viewer::FrameDisplay> display_;
    std::unique_ptr<viewer::Panel> panel_;  // null with --no-panel, or when it cannot start (panel_error_)
    std::string panel_error_;
    viewer::HeldKeys held_keys_;
    size_t next_key_ = 0, next_drop_ = 0;
    bool help_ = false;
    bool need_render_ = true;          // something changed that the frame shown does not have yet (the first frame too)
    bool last_render_scaled_ = false;  // the last frame was rendered below full resolution: refine when still
    uint32_t full_width_ = 0, full_height_ = 0;        // the window's framebuffer (offscreen: --width/--height)
    uint32_t display_width_ = 0, display_height_ = 0;  // the frame size the display was made for
    std::string message_;
    bool message_is_error_ = false;
    FrameResult last_frame_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();  // the first frame
    uint32_t frames_rendered_ = 0;
    uint64_t frames_shown_ = 0;
    double frame_interval_ms_ = 0.0;  // smoothed time between presented frames while rendering continuously
    int files_loaded_ = 0, load_errors_ = 0;
    viewer::FrameTimings stats_;
    viewer::GlTimer gl_timer_;
    int backend_switches_ = 0;
    std::string ablate_;  // PRISM_VIEW_ABLATE: "", "copy" or "gl"
};

void run_view(const ViewOptions& options) {
    check_frame_options(options.backend, options.settings);  // before the window or the scene
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
    throw Error(
        "view: not available in this build (GLFW or OpenGL not found at configure time: "
        "apt-get install libglfw3-dev libgl-dev and reconfigure)");
}

#endif

}  // namespace

void add_view_command(CLI::App& app) {
    auto options = std::make_shared<ViewOptions>();
    auto* command = app.add_subcommand("view", "Interactive preview in a window (GLFW + OpenGL)");
    add_scene_options(command, options->scene);
    command
        ->add_option("--backend", options->backend,
                     "auto, cpu-ref, cpu, cuda, opencl, vulkan; a device after a colon (opencl:pocl)")
        ->capture_default_str();
    command->add_option("--width", options->settings.width, "window and frame width")->capture_default_str();
    command->add_option("--height", options->settings.height, "window and frame height")->capture_default_str();
    command->add_option("--depth", options->settings.max_depth, "ray generations traced (+/- change it)")
        ->capture_default_str();
    add_display_options(command, options->settings);
    command
        ->add_option("--frames", options->frames,
                     "render this many frames, one on every pass, and exit (0: until Esc, rendering only when "
                     "something changes)")
        ->capture_default_str();
    command
        ->add_option(
            "--seconds", options->seconds,
            "stop after this many seconds of wall-clock time (0: no limit; with --frames, whichever ends first)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--screenshot", options->screenshot,
                        "with --frames: save the last frame as read back from the window (.png)");
    command->add_flag("--no-vsync", options->no_vsync, "present without waiting for vertical sync");
    command->add_option("--keys", options->keys,
                        "scripted key presses FRAME:KEY,... (keys 1-5 + - P R M F H L Esc W A S D Q E; a fly key held "
                        "for SECONDS with FRAME:KEY:SECONDS), e.g. 0:M,3:2,4:W:1.5");
    command->add_option("--drop", options->drops,
                        "scripted file drop FRAME:PATH (repeatable): loaded as if dropped onto the window");
    command->add_flag("--no-panel", options->no_panel, "no on-screen panel: the frame alone (also PRISM_VIEW_PANEL=0)");
    command
        ->add_option("--interactive-scale", options->interactive_scale,
                     "resolution while the camera or scene moves: auto (to hold --target-fps) or a fraction in "
                     "(0, 1] of the window's; full resolution once it stops")
        ->capture_default_str();
    command
        ->add_option("--target-fps", options->target_fps, "frame rate --interactive-scale auto aims for while moving")
        ->capture_default_str();
    command
        ->add_option("--display", options->display,
                     "how frames reach the window: auto (GPU buffer interop where the backend and GL allow it, "
                     "else host copy), interop (required), host-copy, none (render only)")
        ->capture_default_str();
    command->add_option("--stats", options->stats,
                        "write the timing summary (median render/display/frame ms, fps, display path) as JSON");
    command
        ->add_option("--alternate-display", options->alternate,
                     "measure what showing a frame costs within one run: N frames shown, then N only rendered, and "
                     "so on; the summary and --stats compare their median frame times (0: show every frame)")
        ->capture_default_str();
    command->add_flag("--headless", options->headless,
                      "draw into an offscreen framebuffer of an EGL context (an EGL device, else Mesa's surfaceless "
                      "platform) instead of a window: no X server needed; input only from --keys");
    command->callback([options] {
        route_output();
        if (setting(Setting::ViewPanel) == "0") options->no_panel = true;
        if (options->headless && options->frames == 0 && options->seconds <= 0.0)
            throw Error("view: --headless needs --frames or --seconds (there is no window to close)");
        run_view(*options);
    });
}

}  // namespace prism::app
