// What is particular to the `opencl` backend, on PoCL (the CPU OpenCL device of CI; the same code runs NVIDIA's
// OpenCL on the GPU machine): the layout contract in OpenCL C, the embedded source and build errors, the program
// cache, device selection, CL_DEVICE_MAX_MEM_ALLOC_SIZE, and the shared kernels run alone. The contract every
// backend keeps is in test_backend_contract.cpp. Every test skips, with the reason, when no OpenCL device answers.
#ifdef PRISM_HAVE_OPENCL

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <optional>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "backends/opencl/opencl_internal.h"
#include "backends/opencl/opencl_register_budgets.h"
#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "kernels/stages.h"
#include "tests/test_support.h"

namespace {

const char* kPocl = "pocl";

#define REQUIRE_POCL()                                                                       \
    do {                                                                                     \
        std::string reason_;                                                                 \
        if (!pocl_available(&reason_)) GTEST_SKIP() << "no OpenCL test device: " << reason_; \
    } while (0)

// The device under test: PoCL in CI, NVIDIA's OpenCL on the GPU machine ($PRISM_TEST_OPENCL_DEVICE).
bool pocl_available(std::string* reason) {
    std::string spec = prism::test::test_device("opencl");
    return prism::test::device_present("opencl", spec.substr(spec.find(':') + 1), reason);
}

using prism::test::ScopedEnv;

}  // namespace

// ---- Layout and program building ------------------------------------------------------------------------------

TEST(OpenclLayout, MarkerKernelMatchesTheTable) {
    REQUIRE_POCL();
    std::vector<uint32_t> expected;
    std::vector<std::string> names;
#define RT_LAYOUT_STRUCT(name, size) expected.push_back(size), names.push_back("sizeof(" #name ")");
#define RT_LAYOUT_MEMBER(name, member, offset, kind) expected.push_back(offset), names.push_back(#name "." #member);
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER
    std::vector<uint32_t> actual = prism::opencl_internal::layout_words(kPocl);
    ASSERT_EQ(actual.size(), expected.size()) << "the marker kernel wrote a different number of entries";
    for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(actual[i], expected[i]) << names[i] << " in OpenCL C";
}

TEST(OpenclProgram, EmbeddedSourceHasEveryIncludeResolved) {
    std::string source = prism::opencl_internal::stages_source();
    EXPECT_NE(source.find("#line 1 \"kernels/stages.h\""), std::string::npos);
    EXPECT_NE(source.find("#line 1 \"kernels/data_arrays.h\""), std::string::npos);
    EXPECT_NE(source.find("rt_kernel_shade"), std::string::npos);
    std::regex quoted_include(R"((^|\n)[ \t]*#[ \t]*include[ \t]*")");
    EXPECT_FALSE(std::regex_search(source, quoted_include)) << "a quoted #include was left for run time";
}

TEST(OpenclProgram, BuildFailureReportsTheCompilerLog) {
    REQUIRE_POCL();
    ScopedEnv no_cache("PRISM_CACHE_DIR", "");
    std::string message = prism::test::error_message([] {
        prism::opencl_internal::build_source(
            kPocl,
            "#line 1 \"kernels/broken.h\"\n__kernel void broken(__global uint* out) { out[0] = undeclared_name; }\n");
    });
    EXPECT_NE(message.find("opencl: kernel build failed on "), std::string::npos) << message;
    EXPECT_NE(message.find("undeclared_name"), std::string::npos) << message;
    EXPECT_NE(message.find("kernels/broken.h:1"), std::string::npos)
        << "the #line file names should survive: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "errors are one line: " << message;
}

TEST(OpenclProgram, BinaryCacheIsWrittenReusedAndOptional) {
    REQUIRE_POCL();
    const std::string source = "__kernel void cached(__global uint* out) { out[get_global_id(0)] = 7u; }\n";
    std::filesystem::path dir = prism::test::temp_dir("opencl-cache");
    std::filesystem::remove_all(dir);
    {
        ScopedEnv env("PRISM_CACHE_DIR", dir.string());
        EXPECT_EQ(prism::opencl_internal::cache_directory(), dir.string());
        prism::opencl_internal::BuildReport first = prism::opencl_internal::build_source(kPocl, source);
        EXPECT_FALSE(first.from_cache);
        ASSERT_FALSE(first.cache_file.empty());
        EXPECT_TRUE(std::filesystem::exists(first.cache_file)) << first.cache_file;
        prism::opencl_internal::BuildReport second = prism::opencl_internal::build_source(kPocl, source);
        EXPECT_TRUE(second.from_cache);
        EXPECT_EQ(second.cache_file, first.cache_file);
        EXPECT_NE(first.options.find("-cl-std=CL1.2"), std::string::npos);
        EXPECT_EQ(first.options.find("fast"), std::string::npos) << "no fast-math on any API: " << first.options;
        // A different source is a different entry.
        prism::opencl_internal::BuildReport other = prism::opencl_internal::build_source(kPocl, source + "\n");
        EXPECT_NE(other.cache_file, first.cache_file);
        // A corrupt entry is rebuilt from source, not trusted.
        std::ofstream(first.cache_file, std::ios::binary | std::ios::trunc) << "garbage";
        prism::opencl_internal::BuildReport rebuilt = prism::opencl_internal::build_source(kPocl, source);
        EXPECT_FALSE(rebuilt.from_cache);
        EXPECT_TRUE(prism::opencl_internal::build_source(kPocl, source).from_cache);
    }
    {
        // An unusable cache directory still builds (just without caching).
        std::filesystem::path blocker = prism::test::write_file("opencl-cache-blocker", "a file, not a directory");
        ScopedEnv env("PRISM_CACHE_DIR", (blocker / "sub").string());
        EXPECT_FALSE(prism::opencl_internal::build_source(kPocl, source).from_cache);
        EXPECT_FALSE(prism::opencl_internal::build_source(kPocl, source).from_cache);
    }
}

// PRISM_OPENCL_OPTIONS (experiments) goes after the fixed options, keys its own cache entry, and a bad option is
// the build's one-line error.
TEST(OpenclProgram, ExtraOptionsFollowTheFixedOnesAndKeyTheCache) {
    REQUIRE_POCL();
    const std::string source = "__kernel void cached(__global uint* out) { out[get_global_id(0)] = EXTRA; }\n";
    std::filesystem::path dir = prism::test::temp_dir("opencl-cache-options");
    std::filesystem::remove_all(dir);
    ScopedEnv cache("PRISM_CACHE_DIR", dir.string());
    prism::opencl_internal::BuildReport one, two;
    {
        ScopedEnv extra("PRISM_OPENCL_OPTIONS", "-D EXTRA=1u");
        one = prism::opencl_internal::build_source(kPocl, source);
        EXPECT_NE(one.options.find("-cl-std=CL1.2 "), std::string::npos) << one.options;
        EXPECT_EQ(one.options.substr(one.options.size() - 11), "-D EXTRA=1u") << one.options;
    }
    {
        ScopedEnv extra("PRISM_OPENCL_OPTIONS", "-D EXTRA=2u");
        two = prism::opencl_internal::build_source(kPocl, source);
        EXPECT_FALSE(two.from_cache);
        EXPECT_NE(two.cache_file, one.cache_file);
    }
    {
        ScopedEnv extra("PRISM_OPENCL_OPTIONS", "-cl-no-such-option");
        std::string message =
            prism::test::error_message([&] { prism::opencl_internal::build_source(kPocl, source + "\n"); });
        EXPECT_NE(message.find("opencl: kernel build failed on "), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "errors are one line: " << message;
    }
}

// ---- Register budgets (opencl_register_budgets.h) ---------------------------------------------------------------

namespace {

// Every stage in exactly one of the programs.
void expect_each_stage_once(const std::vector<prism::opencl::StageProgram>& programs) {
    uint32_t seen = 0;
    for (const prism::opencl::StageProgram& p : programs) {
        EXPECT_EQ(seen & p.stages, 0u) << "a stage in two programs";
        seen |= p.stages;
    }
    EXPECT_EQ(seen, (1u << prism::stage_count) - 1u);
}

uint32_t stage_bit(prism::Stage stage) { return 1u << static_cast<unsigned>(stage); }

}  // namespace

TEST(OpenclRegisterBudgets, OneProgramWhereTheDeviceCannotTakeThem) {
    for (std::optional<std::string> setting : {std::optional<std::string>(), std::optional<std::string>("shade=96")}) {
        std::vector<prism::opencl::StageProgram> programs = prism::opencl::stage_programs(false, setting);
        ASSERT_EQ(programs.size(), 1u);
        EXPECT_EQ(programs[0].options, "") << "the plain program, as before budgets";
        expect_each_stage_once(programs);
    }
}

// CUDA's budgets (backends/cuda/stages.cu): the one-mesh walks at 56 registers, the other traversal stages at 64,
// shade at 128, the rest free.
TEST(OpenclRegisterBudgets, OnNvidiaTheStagesGetCudasBudgets) {
    std::vector<prism::opencl::StageProgram> programs = prism::opencl::stage_programs(true, std::nullopt);
    ASSERT_EQ(programs.size(), 4u);
    expect_each_stage_once(programs);
    const uint32_t mesh = stage_bit(prism::Stage::IntersectMesh) | stage_bit(prism::Stage::OccludeMesh);
    const uint32_t traversal =
        stage_bit(prism::Stage::Intersect) | stage_bit(prism::Stage::Occlude) | stage_bit(prism::Stage::Shadow);
    const uint32_t shade = stage_bit(prism::Stage::Shade);
    const uint32_t others = ((1u << prism::stage_count) - 1u) & ~mesh & ~traversal & ~shade;
    EXPECT_EQ(programs[0].stages, others);
    EXPECT_EQ(programs[0].options, "-D RT_CL_STAGE_MASK=" + std::to_string(others) + "u");
    EXPECT_EQ(programs[1].stages, mesh);
    EXPECT_EQ(programs[1].options, "-D RT_CL_STAGE_MASK=" + std::to_string(mesh) + "u -cl-nv-maxrregcount=56");
    EXPECT_EQ(programs[2].stages, traversal);
    EXPECT_EQ(programs[2].options, "-D RT_CL_STAGE_MASK=" + std::to_string(traversal) + "u -cl-nv-maxrregcount=64");
    EXPECT_EQ(programs[3].stages, shade);
    EXPECT_EQ(programs[3].options, "-D RT_CL_STAGE_MASK=" + std::to_string(shade) + "u -cl-nv-maxrregcount=128");
}

TEST(OpenclRegisterBudgets, TheSettingReplacesTheTable) {
    std::vector<prism::opencl::StageProgram> programs =
        prism::opencl::stage_programs(true, "intersect=64,shadow=64,shade=160");
    ASSERT_EQ(programs.size(), 3u);
    expect_each_stage_once(programs);
    EXPECT_EQ(programs[1].stages, stage_bit(prism::Stage::Intersect) | stage_bit(prism::Stage::Shadow));
    EXPECT_NE(programs[1].options.find("-cl-nv-maxrregcount=64"), std::string::npos) << programs[1].options;
    EXPECT_NE(programs[2].options.find("-cl-nv-maxrregcount=160"), std::string::npos) << programs[2].options;
    for (const char* none : {"none", ""}) {
        programs = prism::opencl::stage_programs(true, std::string(none));
        ASSERT_EQ(programs.size(), 1u) << none;
        EXPECT_EQ(programs[0].options, "") << none;
    }
}

TEST(OpenclRegisterBudgets, AMalformedSettingIsOneLineNamingIt) {
    for (const char* bad : {"shade", "light=64", "shade=8", "shade=256", "shade=12x", "shade=-1", "shade=128,"}) {
        std::string message =
            prism::test::error_message([&] { prism::opencl::stage_programs(true, std::string(bad)); });
        EXPECT_NE(message.find(std::string("opencl: PRISM_OPENCL_REGISTERS='") + bad + "': "), std::string::npos)
            << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

// A program built for some stages holds only their entry points (what lets each budget compile only its stages).
TEST(OpenclRegisterBudgets, AStageMaskBuildsOnlyThoseEntryPoints) {
    REQUIRE_POCL();
    ScopedEnv no_cache("PRISM_CACHE_DIR", "");
    const uint32_t mask = stage_bit(prism::Stage::Miss) | stage_bit(prism::Stage::Resolve);
    prism::opencl_internal::BuildReport report = prism::opencl_internal::build_source(
        kPocl, prism::opencl_internal::stages_source(), "-D RT_CL_STAGE_MASK=" + std::to_string(mask) + "u");
    std::vector<std::string> names;
    std::istringstream list(report.kernel_names);
    for (std::string name; std::getline(list, name, ';');) names.push_back(name);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"prism_miss", "prism_resolve"})) << report.kernel_names;
}

// ---- Device selection -------------------------------------------------------------------------------------------

TEST(OpenclDevices, UnknownFilterListsTheDevices) {
    REQUIRE_POCL();
    std::string message = prism::test::error_message([] { prism::create_backend("opencl:no-such-device-xyz"); });
    EXPECT_NE(message.find("opencl: device 'no-such-device-xyz' not found"), std::string::npos) << message;
    EXPECT_NE(message.find("Portable Computing Language ["), std::string::npos) << message;
}

TEST(OpenclDevices, FiltersAreCaseInsensitiveSubstrings) {
    REQUIRE_POCL();
    EXPECT_NE(prism::create_backend("opencl:POCL")->info().device, "");
    EXPECT_NE(prism::create_backend("opencl:portable computing")->info().device, "");
    auto backend = prism::create_backend("opencl");  // the default: a GPU if any, else the first device
    prism::BackendInfo info = backend->info();
    EXPECT_EQ(info.name, "opencl");
    EXPECT_NE(info.api_version.find("OpenCL"), std::string::npos) << info.api_version;
    EXPECT_GT(info.device_memory, 0u);
    EXPECT_GT(info.max_buffer, 0u);
}

TEST(OpenclDevices, ProbeListsEveryDevice) {
    REQUIRE_POCL();
    for (const prism::BackendFactory& f : prism::registered_backends()) {
        if (f.name != "opencl") continue;
        prism::BackendAvailability a = f.probe();
        EXPECT_TRUE(a.available);
        ASSERT_FALSE(a.devices.empty());
        EXPECT_NE(a.devices.front().find("compute units"), std::string::npos) << a.devices.front();
    }
}

// Without a driver the backend is reported unavailable with the reason, and asking for it is a one-line error
// (the ICD loader in a child process is pointed at an empty vendor directory).
TEST(OpenclDevices, NoDriverIsReportedNotCrashed) {
    std::filesystem::path empty = prism::test::temp_dir("opencl-no-vendors");
    ScopedEnv vendors("OCL_ICD_VENDORS", empty.string());
    prism::test::CommandResult info = prism::test::run_prism("info");
    EXPECT_EQ(info.exit_code, 0) << info.output;
    if (info.output.find("opencl   available") != std::string::npos)
        GTEST_SKIP() << "this machine's ICD loader finds a driver without OCL_ICD_VENDORS (not testable here)";
    EXPECT_NE(info.output.find("no OpenCL platform (ICD loader found no driver)"), std::string::npos) << info.output;
    std::filesystem::path out = empty / "never.png";
    prism::test::CommandResult render =
        prism::test::run_prism("render --backend opencl --width 8 --height 8 --out '" + out.string() + "'");
    EXPECT_EQ(render.exit_code, 1) << render.output;
    EXPECT_NE(render.output.find("prism: error: opencl: no OpenCL platform"), std::string::npos) << render.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// ---- Memory, launches, timers (no scene needed) -----------------------------------------------------------------

TEST(OpenclBackend, OversizedBuffersAreRefusedWithTheLimit) {
    REQUIRE_POCL();
    auto backend = prism::create_backend(prism::test::test_device("opencl"));
    prism::BackendInfo info = backend->info();
    std::string message =
        prism::test::error_message([&] { backend->allocate(prism::DeviceArray::rays, info.max_buffer + 1); });
    EXPECT_NE(message.find("buffer 'rays'"), std::string::npos) << message;
    EXPECT_NE(message.find("CL_DEVICE_MAX_MEM_ALLOC_SIZE"), std::string::npos) << message;
}

// generate + resolve on an empty frame: primary rays equal the C++ compilation of the same function, the image is
// black, and finish() returns one device timing per launch.
TEST(OpenclBackend, GenerateAndResolveRunTheSharedKernels) {
    REQUIRE_POCL();
    auto backend = prism::create_backend(prism::test::test_device("opencl"));
    const uint32_t width = 37, height = 23, pixels = width * height;  // not a multiple of the work-group size
    FrameParams frame{};
    frame.camera_position = float4{1.0f, 2.0f, 3.0f, 0.0f};
    frame.camera_forward = float4{0.0f, 0.0f, -1.0f, 0.0f};
    frame.camera_right = float4{1.0f, 0.0f, 0.0f, 0.0f};
    frame.camera_up = float4{0.0f, 1.0f, 0.0f, 0.0f};
    frame.tan_half_fov = 0.5f;
    frame.aspect = float(width) / float(height);
    frame.width = width;
    frame.height = height;
    frame.max_depth = 1;
    frame.ray_capacity = frame.shadow_capacity = pixels;
    frame.tile_width = width;
    frame.tile_height = height;
    std::vector<uint32_t> counters(RT_COUNTER_SLOTS, 0u);
    counters[RT_COUNTER_RAYS] = pixels;
    backend->allocate(prism::DeviceArray::frame, sizeof frame);
    backend->write(prism::DeviceArray::frame, &frame, sizeof frame);
    backend->allocate(prism::DeviceArray::counters, counters.size() * 4);
    backend->write(prism::DeviceArray::counters, counters.data(), counters.size() * 4);
    backend->allocate(prism::DeviceArray::rays, size_t(pixels) * 2 * sizeof(Ray));
    backend->allocate(prism::DeviceArray::accum, size_t(pixels) * RT_ACCUM_WORDS_PER_PIXEL * 4);
    backend->allocate(prism::DeviceArray::image, size_t(pixels) * 4);
    backend->allocate(prism::DeviceArray::radiance, size_t(pixels) * sizeof(float4));
    backend->zero(prism::DeviceArray::accum);
    backend->enqueue(prism::Stage::Generate, 0);
    backend->enqueue(prism::Stage::Resolve, 0);
    std::vector<prism::StageTiming> timings = backend->finish();
    ASSERT_EQ(timings.size(), 2u);
    EXPECT_EQ(timings[0].stage, prism::Stage::Generate);
    EXPECT_EQ(timings[1].stage, prism::Stage::Resolve);
    for (const prism::StageTiming& t : timings) {
        EXPECT_GT(t.milliseconds, 0.0);
        EXPECT_LT(t.milliseconds, 1e6);
    }
    EXPECT_TRUE(backend->finish().empty()) << "finish() returns only what was enqueued since the last one";

    std::vector<Ray> rays(pixels);
    backend->read(prism::DeviceArray::rays, rays.data(), rays.size() * sizeof(Ray));
    for (uint32_t i = 0; i < pixels; ++i) {
        Ray expected = rt_primary_ray(frame, i);
        ASSERT_EQ(rays[i].pixel, i);
        EXPECT_NEAR(rays[i].direction.x, expected.direction.x, 1e-6f) << i;
        EXPECT_NEAR(rays[i].direction.y, expected.direction.y, 1e-6f) << i;
        EXPECT_NEAR(rays[i].direction.z, expected.direction.z, 1e-6f) << i;
        EXPECT_EQ(rays[i].origin.x, 1.0f);
    }
    std::vector<uint32_t> image(pixels);
    backend->read(prism::DeviceArray::image, image.data(), image.size() * 4);
    EXPECT_EQ(image, std::vector<uint32_t>(pixels, 0xff000000u));
}

// ---- Agreement with cpu-ref -------------------------------------------------------------------------------------

#endif  // PRISM_HAVE_OPENCL
