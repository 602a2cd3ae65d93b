// Helpers shared by the tests: where the assets are, temporary files, running the prism command.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/render/device_scene.h"
#include "core/render/renderer.h"
#include "core/scene/scene.h"
#include "core/util/non_copyable.h"

namespace prism::test {

// ../shared/scenes (or $PRISM_SCENES_DIR).
std::filesystem::path scenes_dir();
std::filesystem::path scene(const std::string& relative);
// A fresh directory for one test, removed by nobody (ctest's build tree is disposable).
std::filesystem::path temp_dir(const std::string& name);
// Writes bytes to a file under temp_dir("files") (whole or not at all: core/util/output_file.h) and returns its path.
std::filesystem::path write_file(const std::string& name, const std::string& bytes);
// The bytes of a file ("" when it cannot be read).
std::string file_bytes(const std::filesystem::path& path);

// The message of the prism::Error that `action` throws, or "(no prism::Error thrown)".
std::string error_message(const std::function<void()>& action);

// Whether this machine runs the named backend ("cuda", "opencl", "vulkan"); `reason` says why not.
bool backend_available(const std::string& name, std::string* reason = nullptr);

// The device the OpenCL/Vulkan tests run on: $PRISM_TEST_OPENCL_DEVICE / $PRISM_TEST_VULKAN_DEVICE, by default the
// software devices CI has ("pocl", "llvmpipe"); the GPU run sets "opencl:nvidia", "vulkan:nvidia" (a bare filter such
// as "nvidia" works too). Returns e.g. "opencl:pocl".
std::string test_device(const std::string& api);
// Whether `api`'s probe lists a device whose name contains `filter` (case-insensitive); `reason` says why not.
bool device_present(const std::string& api, const std::string& filter, std::string* reason = nullptr);

// A scene: "builtin:x", a path under scenes_dir(), or "examples/<file>.json", one of docs/examples' scene files
// (which read the shared scenes beside the repository).
prism::Scene load_test_scene(const std::string& spec);
// The same, built with `layout` (resolve_bvh_layout("auto", backend) for the layout a backend renders with); the
// camera and the rest of the scene in `*scene` when given.
prism::DeviceScene load_device_scene(const std::string& spec, prism::Scene* scene, prism::BvhLayout layout);

// `scene` as it stands `seconds` into its motion, with nothing left to move: instances, lights and camera placed and
// deformed meshes posed (a scene built from it is what RenderEngine::move_to must trace).
prism::Scene scene_posed_at(const prism::Scene& scene, double seconds);

// A gtest name from a backend spec or a scene's file name: every character but letters and digits made '_'.
std::string test_name_of(const std::string& text);

// Settings for a small test frame: width x height, `max_depth` generations (RenderSettings' default when omitted).
inline prism::RenderSettings small_settings(uint32_t width, uint32_t height,
                                            uint32_t max_depth = prism::RenderSettings{}.max_depth) {
    prism::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.max_depth = max_depth;
    return settings;
}

// Whether a backend spec ("cpu", "cuda", "opencl:pocl", ...) runs here: its API is built and, for OpenCL and
// Vulkan, the probe lists a device matching its filter. `reason` says why not.
bool backend_spec_runs_here(const std::string& spec, std::string* reason);

// Checks a backend test runs under: for Vulkan, VK_LAYER_KHRONOS_validation on (PRISM_VULKAN_VALIDATION=1, with a
// private XDG_RUNTIME_DIR so the loader stays quiet) and its messages collected from here on. Call before creating
// the backend; `backend_check_messages` then returns what the layer or driver reported (empty: clean).
void begin_backend_checks(const std::string& spec);
std::vector<std::string> backend_check_messages(const std::string& spec);

// Ray counts per depth of a GPU frame against the reference: equal up to rounding (FMA contraction and division
// precision may tip a grazing ray or light the other way, and glass compounds it over depths: measured up to 0.2%
// at depth 5 of the dragon on an H100; allowed 0.5% or 8 rays per depth).
void expect_ray_counts_near(const prism::FrameStats& expected, const prism::FrameStats& actual);

// Peak signal-to-noise ratio of two RGBA8 images over the RGB channels; +inf when identical.
double psnr_rgba8(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b);

struct CommandResult {
    int exit_code = -1;  // the process exit status; 128 + signal when killed by a signal
    std::string output;  // stdout and stderr together
};
// Runs the prism binary with the given arguments (a shell-quoted string), after `launcher` when one is given
// (e.g. "xvfb-run -a" for the viewer, "env -u DISPLAY").
CommandResult run_prism(const std::string& arguments, const std::string& launcher = "");

// `prism render --scene scene_file` (cpu backend, a small image) fails as the project rule says bad input must:
// one line "prism: error: ..." mentioning `must_mention`, exit code 1..127, no output file nor temporary left.
void expect_clean_failure(const std::string& scene_file, const std::string& must_mention);

// Sets an environment variable for one scope (backends read theirs when created), then restores it.
class ScopedEnv : private NonCopyable {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (old_)
            setenv(name_, old_->c_str(), 1);
        else
            unsetenv(name_);
    }

private:
    const char* name_;
    std::optional<std::string> old_;
};

}  // namespace prism::test
