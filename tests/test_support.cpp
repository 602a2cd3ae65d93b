#include "tests/test_support.h"

#include "backends/backend_list.h"
#include "core/render/backend.h"
#include "core/util/error.h"
#include "core/util/output_file.h"
#include "core/image/image_compare.h"
#include "core/loaders/scene_loader.h"
#include "core/scene/scene_motion.h"
#ifdef PRISM_HAVE_VULKAN
#include "backends/vulkan/vulkan_backend.h"
#endif

#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace prism::test {

// Every test binary sees the same backends as the prism command.
static const bool backends_registered = (prism::register_builtin_backends(), true);

std::filesystem::path scenes_dir() {
    if (const char* dir = std::getenv("PRISM_SCENES_DIR")) return dir;
    return PRISM_SCENES_DIR;
}

std::filesystem::path scene(const std::string& relative) { return scenes_dir() / relative; }

std::filesystem::path temp_dir(const std::string& name) {
    std::filesystem::path base = std::getenv("PRISM_TEST_TMP") ? std::getenv("PRISM_TEST_TMP")
                                                               : std::filesystem::temp_directory_path() / "prism";
    std::filesystem::path dir = base / name;
    std::filesystem::create_directories(dir);
    return dir;
}

std::filesystem::path write_file(const std::string& name, const std::string& bytes) {
    // ctest runs test processes side by side and several write the same file (a shared test texture): written under
    // a name of this process's own and renamed into place, a reader never sees one half written.
    std::filesystem::path path = temp_dir("files") / name;
    prism::write_file_atomically(path, bytes);
    return path;
}

std::string error_message(const std::function<void()>& action) {
    try {
        action();
    } catch (const prism::Error& error) {
        return error.what();
    }
    return "(no prism::Error thrown)";
}

bool backend_available(const std::string& name, std::string* reason) {
    prism::register_builtin_backends();
    for (const prism::BackendFactory& factory : prism::registered_backends()) {
        if (factory.name != name) continue;
        prism::BackendAvailability availability = factory.probe();
        if (reason) *reason = availability.detail;
        return availability.available;
    }
    if (reason) *reason = name + " is not compiled into this build";
    return false;
}

std::string test_device(const std::string& api) {
    std::string variable = "PRISM_TEST_" + api + "_DEVICE";
    for (char& c : variable) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const char* value = std::getenv(variable.c_str());
    std::string chosen = value && *value ? value : (api == "vulkan" ? "llvmpipe" : "pocl");
    return chosen.find(':') != std::string::npos ? chosen : api + ":" + chosen;  // "nvidia" or "vulkan:nvidia"
}

bool device_present(const std::string& api, const std::string& filter, std::string* reason) {
    if (!backend_available(api, reason)) return false;
    auto lower = [](std::string text) {
        for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return text;
    };
    for (const prism::BackendFactory& factory : prism::registered_backends()) {
        if (factory.name != api) continue;
        for (const std::string& device : factory.probe().devices)
            if (lower(device).find(lower(filter)) != std::string::npos) return true;
    }
    if (reason) *reason = api + " runs here, but no device matches '" + filter + "'";
    return false;
}

prism::Scene load_test_scene(const std::string& spec) {
    prism::LoadOptions options;
    options.data_dir = scenes_dir();
    const bool example = spec.rfind("examples/", 0) == 0;
    options.allow_any_path = example;  // the examples name ../shared/scenes from docs/examples
    const std::string path = spec.rfind("builtin:", 0) == 0 ? spec
                             : example ? (std::filesystem::path(PRISM_SOURCE_DIR) / "docs" / spec).string()
                                       : prism::test::scene(spec).string();
    return prism::load_scene(path, options);
}

prism::DeviceScene load_device_scene(const std::string& spec, prism::Scene* out, prism::BvhLayout layout) {
    prism::Scene loaded = load_test_scene(spec);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    prism::DeviceScene device = prism::build_device_scene(loaded, bvh);
    if (out) *out = std::move(loaded);
    return device;
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

prism::Scene scene_posed_at(const prism::Scene& scene, double seconds) {
    prism::Scene posed = scene;
    const std::vector<glm::mat4> transforms = prism::instance_transforms_at(scene, seconds);
    for (size_t i = 0; i < transforms.size(); ++i) posed.instances[i].transform = transforms[i];
    const std::vector<prism::DeformedVertices> meshes = prism::deformed_meshes_at(scene.animation, seconds);
    for (size_t d = 0; d < meshes.size(); ++d) {
        prism::Mesh& mesh = posed.meshes[scene.animation.deformations[d].mesh];
        mesh.positions = meshes[d].positions;
        mesh.normals = meshes[d].normals;
        mesh.tangents = meshes[d].tangents;
    }
    posed.lights = prism::lights_at(scene, seconds);
    posed.camera = prism::camera_at(scene, seconds);
    posed.animation = {};
    posed.spins.clear();
    return posed;
}

std::string test_name_of(const std::string& text) {
    std::string name = text;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

bool backend_spec_runs_here(const std::string& spec, std::string* reason) {
    prism::BackendSpec parsed = prism::parse_backend_spec(spec);
    if (parsed.api == "opencl" || parsed.api == "vulkan")
        return device_present(parsed.api, parsed.device_filter, reason);
    if (parsed.api == "cuda") return backend_available("cuda", reason);
    return true;  // the cpu backends are always built
}

void begin_backend_checks(const std::string& spec) {
#ifdef PRISM_HAVE_VULKAN
    if (prism::parse_backend_spec(spec).api != "vulkan") return;
    static bool environment = [] {
        std::string runtime = temp_dir("vulkan-xdg-runtime").string();
        chmod(runtime.c_str(), 0700);
        setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
        setenv("PRISM_VULKAN_VALIDATION", "1", 1);
        return true;
    }();
    (void)environment;
    prism::vulkan_clear_debug_messages();
#else
    (void)spec;
#endif
}

std::vector<std::string> backend_check_messages(const std::string& spec) {
#ifdef PRISM_HAVE_VULKAN
    if (prism::parse_backend_spec(spec).api == "vulkan") return prism::vulkan_debug_messages();
#else
    (void)spec;
#endif
    return {};
}

void expect_ray_counts_near(const prism::FrameStats& expected, const prism::FrameStats& actual) {
    auto near = [](const std::vector<uint32_t>& e, const std::vector<uint32_t>& a, const char* what) {
        ASSERT_EQ(e.size(), a.size()) << what;
        for (size_t d = 0; d < e.size(); ++d)
            EXPECT_LE(std::abs(double(e[d]) - double(a[d])), std::max(8.0, e[d] * 5e-3)) << what << " at depth " << d;
    };
    near(expected.rays_per_depth, actual.rays_per_depth, "rays");
    near(expected.shadow_rays_per_depth, actual.shadow_rays_per_depth, "shadow rays");
}

double psnr_rgba8(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) { return prism::psnr_rgba8(a, b); }

namespace {
std::string shell_quoted(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}
}  // namespace

CommandResult run_prism(const std::string& arguments, const std::string& launcher) {
    CommandResult result;
    // $PRISM_BINARY overrides the build-time path (the tests run from a copied build on the GPU machine).
    const char* binary = std::getenv("PRISM_BINARY") ? std::getenv("PRISM_BINARY") : PRISM_BINARY;
    std::string program = "'" + std::string(binary) + "' " + arguments + " 2>&1";
    // Under xvfb-run, prism's own exit status goes through a file: xvfb-run replaces it with 5 when removing its
    // temporary folder fails after the program has finished (seen once in CI), which says nothing about prism.
    std::filesystem::path status_file;
    if (launcher.rfind("xvfb-run", 0) == 0) {
        static int calls = 0;
        status_file = temp_dir("xvfb-status") / (std::to_string(::getpid()) + "-" + std::to_string(++calls));
        std::filesystem::remove(status_file);
        program = "sh -c " + shell_quoted(program + "; echo $? > '" + status_file.string() + "'");
    }
    std::string command = (launcher.empty() ? "" : launcher + " ") + program + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
    int status = pclose(pipe);
    if (WIFEXITED(status))
        result.exit_code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status))
        result.exit_code = 128 + WTERMSIG(status);
    if (!status_file.empty()) {
        std::ifstream recorded(status_file);
        int code = -1;
        if (recorded >> code) {
            result.exit_code = code;
            const std::string cleanup = "xvfb-run: error: problem while cleaning up temporary directory\n";
            if (size_t at = result.output.find(cleanup); at != std::string::npos)
                result.output.erase(at, cleanup.size());
        }
    }
    return result;
}

namespace {
size_t count_lines(const std::string& text) {
    size_t lines = 0;
    for (char c : text) lines += c == '\n';
    return lines + (!text.empty() && text.back() != '\n');
}
}  // namespace

void expect_clean_failure(const std::string& scene_file, const std::string& must_mention) {
    // A folder of this process's own: the check below for half-written files must not see another test's,
    // written at the same time by a process ctest runs beside this one.
    std::string folder = "clean-failure-";  // appended: GCC 12 warns falsely (-Wrestrict) on "literal" + string
    folder += std::to_string(::getpid());
    std::filesystem::path out = temp_dir(folder) / (std::filesystem::path(scene_file).filename().string() + ".png");
    std::filesystem::remove(out);
    CommandResult r = run_prism("render --scene '" + scene_file + "' --backend cpu --width 32 --height 24 --out '" +
                                out.string() + "'");
    EXPECT_GE(r.exit_code, 1) << r.output;
    EXPECT_LT(r.exit_code, 128) << r.output;
    EXPECT_EQ(count_lines(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("prism: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(must_mention), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
    for (const auto& entry : std::filesystem::directory_iterator(out.parent_path()))
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    std::filesystem::remove_all(out.parent_path());
}

}  // namespace prism::test
