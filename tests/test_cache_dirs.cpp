// Caches must never cost a render. Each software device renders through `prism render` with its cache folders
// pointed beneath a regular file, which no one can create (CI runs as root, and root ignores permission bits but
// not ENOTDIR): PoCL's ($POCL_CACHE_DIR, $XDG_CACHE_HOME, $HOME), Mesa's for lavapipe ($MESA_SHADER_CACHE_DIR,
// $XDG_CACHE_HOME, $HOME) and Prism's own OpenCL program cache ($PRISM_CACHE_DIR, $XDG_CACHE_HOME, $HOME). Each
// must exit 0 with the image a writable cache gives.
#include <filesystem>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "core/image/image_io.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

struct Render {
    prism::test::CommandResult command;
    std::vector<uint32_t> texels;  // empty when no image was written
};

const std::string kCacheVariables[] = {"POCL_CACHE_DIR", "PRISM_CACHE_DIR", "XDG_CACHE_HOME", "MESA_SHADER_CACHE_DIR"};

// `env` arguments that unset every cache variable, then set `assignments` ("NAME=value ..."): each test controls
// exactly which location the drivers fall back to.
std::string environment(const std::string& assignments) {
    std::string command = "env";
    for (const std::string& name : kCacheVariables) command += " -u " + name;
    return command + " " + assignments;
}

Render render(const std::string& backend, const std::string& assignments, const std::string& name) {
    const fs::path out = prism::test::temp_dir("cache-dirs") / (name + ".png");
    fs::remove(out);
    Render result;
    result.command = prism::test::run_prism("render --scene builtin:sphere --backend " + backend +
                                                " --width 64 --height 48 --depth 3 --out '" + out.string() + "'",
                                            environment(assignments));
    if (fs::exists(out)) result.texels = prism::load_texture(out, false).texels;
    return result;
}

// A location nobody can create: a folder path beneath a regular file.
std::string blocked(const std::string& name) {
    const fs::path blocker = prism::test::write_file("cache-blocker-" + name, "a regular file, not a folder");
    return (blocker / "cache").string();
}

// The image with every cache writable, once per backend and process. The cache folders are kept between test
// processes (ctest runs each test alone), so only the first reference render compiles kernels and shaders from
// scratch; the image is named for the test, as ctest -j2 runs two of these processes at once.
const Render& reference(const std::string& backend) {
    static std::map<std::string, Render> done;
    auto found = done.find(backend);
    if (found != done.end()) return found->second;
    const std::string api = backend.substr(0, backend.find(':'));
    const std::string name =
        api + "-" + prism::test::test_name_of(::testing::UnitTest::GetInstance()->current_test_info()->name());
    const fs::path root = prism::test::temp_dir("cache-dirs-writable-" + api);
    const std::string writable = "POCL_CACHE_DIR='" + (root / "pocl").string() + "' PRISM_CACHE_DIR='" +
                                 (root / "prism").string() + "' MESA_SHADER_CACHE_DIR='" + (root / "mesa").string() +
                                 "' XDG_CACHE_HOME='" + (root / "xdg").string() + "'";
    return done.emplace(backend, render(backend, writable, "reference-" + name)).first->second;
}

void expect_same_image(const std::string& backend, const std::string& assignments, const std::string& name) {
    const Render& expected = reference(backend);
    ASSERT_EQ(expected.command.exit_code, 0) << expected.command.output;
    ASSERT_FALSE(expected.texels.empty());
    const Render blocked_render = render(backend, assignments, name);
    EXPECT_EQ(blocked_render.command.exit_code, 0) << assignments << "\n" << blocked_render.command.output;
    EXPECT_EQ(blocked_render.command.output.find("error"), std::string::npos) << blocked_render.command.output;
    EXPECT_TRUE(blocked_render.texels == expected.texels) << assignments << ": the image differs";
}

#define REQUIRE_DEVICE(api, filter)                                                                          \
    do {                                                                                                     \
        std::string why;                                                                                     \
        if (!prism::test::device_present(api, filter, &why)) GTEST_SKIP() << "no " << filter << ": " << why; \
    } while (0)

}  // namespace

// PoCL refused to start without its cache folder ("no OpenCL device"); Prism now gives it a private one.
TEST(CacheDirs, PoclRendersWithPoclCacheDirUnwritable) {
    REQUIRE_DEVICE("opencl", "pocl");
    const std::string location = blocked("pocl");
    expect_same_image("opencl:pocl", "POCL_CACHE_DIR='" + location + "'", "pocl-cache-dir");
    const Render again = render("opencl:pocl", "POCL_CACHE_DIR='" + location + "'", "pocl-cache-dir-warning");
    EXPECT_NE(again.command.output.find("prism: warning: PoCL cannot use its kernel cache " + location),
              std::string::npos)
        << again.command.output;
}

// One cache location made unwritable at a time (the others unset): the render succeeds with the same image.
// XDG_CACHE_HOME is where PoCL ($XDG_CACHE_HOME/pocl), Mesa and Prism ($XDG_CACHE_HOME/prism) look by default;
// without any cache variable everything falls back to $HOME/.cache.
struct BlockedCache {
    std::string backend;                 // "opencl:pocl" or "vulkan:llvmpipe"
    std::vector<std::string> variables;  // the variables pointed at blocked locations
    std::string name;
};
void PrintTo(const BlockedCache& c, std::ostream* os) { *os << c.name; }

class CacheDirsBlocked : public ::testing::TestWithParam<BlockedCache> {};

TEST_P(CacheDirsBlocked, RenderTheSameImage) {
    const BlockedCache& c = GetParam();
    const prism::BackendSpec spec = prism::parse_backend_spec(c.backend);
    REQUIRE_DEVICE(spec.api, spec.device_filter);
    std::string assignments;
    for (const std::string& variable : c.variables)
        assignments += variable + "='" + blocked(c.name + "-" + variable) + "' ";
    expect_same_image(c.backend, assignments, c.name);
}

INSTANTIATE_TEST_SUITE_P(
    CacheDirs, CacheDirsBlocked,
    ::testing::Values(BlockedCache{"opencl:pocl", {"PRISM_CACHE_DIR"}, "PoclPrismCacheDir"},
                      BlockedCache{"opencl:pocl", {"XDG_CACHE_HOME"}, "PoclXdgCacheHome"},
                      BlockedCache{"opencl:pocl", {"HOME"}, "PoclHome"},
                      BlockedCache{"vulkan:llvmpipe", {"MESA_SHADER_CACHE_DIR"}, "LavapipeMesaShaderCacheDir"},
                      BlockedCache{"vulkan:llvmpipe", {"XDG_CACHE_HOME", "HOME"}, "LavapipeXdgCacheHomeAndHome"}),
    [](const auto& info) { return info.param.name; });
