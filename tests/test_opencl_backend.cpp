// The `opencl` backend on PoCL (the CPU OpenCL device of CI; the same code runs NVIDIA's OpenCL on the H100):
// layout contract, build errors, device selection, program cache, memory, timings, and agreement of images and
// ray queries with the cpu-ref oracle. Every test skips, with the reason, when no OpenCL device answers.
#ifdef PRISM_HAVE_OPENCL

#include <cmath>
#include <functional>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "backends/opencl/opencl_internal.h"
#include "core/error.h"
#include "core/render_engine.h"
#include "core/scene_loader.h"
#include "kernels/stages.h"
#include "tests/test_support.h"

namespace {

const char* kPocl = "pocl";

#define REQUIRE_POCL()                                                                         \
    do {                                                                                       \
        std::string reason_;                                                                   \
        if (!pocl_available(&reason_)) GTEST_SKIP() << "no OpenCL test device: " << reason_; \
    } while (0)

// The device under test: PoCL in CI, NVIDIA's OpenCL on the GPU machine ($PRISM_TEST_OPENCL_DEVICE).
bool pocl_available(std::string* reason) {
    std::string spec = prism::test::test_device("opencl");
    return prism::test::device_present("opencl", spec.substr(spec.find(':') + 1), reason);
}

using prism::test::ScopedEnv;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const prism::Error& e) {
        return e.what();
    }
    return "";
}

// The BVH layout is the one the renderer would pick for this backend: stack, or $PRISM_BVH_LAYOUT (so the whole
// suite can run on another layout); the tests that name a layout pass it.
prism::DeviceScene load(const std::string& spec, prism::Scene* out,
                        prism::BvhLayout layout = prism::resolve_bvh_layout("auto", "opencl")) {
    prism::LoadOptions options;
    options.data_dir = prism::test::scenes_dir();
    std::string resolved = spec.rfind("builtin:", 0) == 0 ? spec : prism::test::scene(spec).string();
    prism::Scene scene = prism::load_scene(resolved, options);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    prism::DeviceScene device = prism::build_device_scene(scene, bvh);
    if (out) *out = std::move(scene);
    return device;
}

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
    std::string message = error_of([] {
        prism::opencl_internal::build_source(
            kPocl, "#line 1 \"kernels/broken.h\"\n__kernel void broken(__global uint* out) { out[0] = undeclared_name; }\n");
    });
    EXPECT_NE(message.find("opencl: kernel build failed on "), std::string::npos) << message;
    EXPECT_NE(message.find("undeclared_name"), std::string::npos) << message;
    EXPECT_NE(message.find("kernels/broken.h:1"), std::string::npos) << "the #line file names should survive: " << message;
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

// ---- Device selection -------------------------------------------------------------------------------------------

TEST(OpenclDevices, UnknownFilterListsTheDevices) {
    REQUIRE_POCL();
    std::string message = error_of([] { prism::create_backend("opencl:no-such-device-xyz"); });
    EXPECT_NE(message.find("opencl: device 'no-such-device-xyz' not found"), std::string::npos) << message;
    EXPECT_NE(message.find("Portable Computing Language ["), std::string::npos) << message;
}

TEST(OpenclDevices, FiltersAreCaseInsensitiveSubstrings) {
    REQUIRE_POCL();
    EXPECT_NE(prism::create_backend("opencl:POCL")->info().device, "");
    EXPECT_NE(prism::create_backend("opencl:portable computing")->info().device, "");
    auto backend = prism::create_backend("opencl");   // the default: a GPU if any, else the first device
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

TEST(OpenclBackend, MemoryRoundTripsAndZeroSizeArraysWork) {
    REQUIRE_POCL();
    auto backend = prism::create_backend(prism::test::test_device("opencl"));
    std::vector<uint32_t> data(1000);
    for (uint32_t i = 0; i < data.size(); ++i) data[i] = i * 2654435761u;
    backend->allocate(prism::DeviceArray::texels, data.size() * 4);
    backend->write(prism::DeviceArray::texels, data.data(), data.size() * 4);
    std::vector<uint32_t> back(data.size());
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_EQ(back, data);
    // Partial write at an offset.
    uint32_t word = 0xdeadbeefu;
    backend->write(prism::DeviceArray::texels, &word, 4, 40);
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_EQ(back[10], word);
    EXPECT_EQ(back[11], data[11]);
    backend->zero(prism::DeviceArray::texels);
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_EQ(back, std::vector<uint32_t>(data.size(), 0u));
    // Zero-size arrays are legal (a scene without textures or lights).
    backend->allocate(prism::DeviceArray::lights, 0);
    backend->write(prism::DeviceArray::lights, nullptr, 0);
    backend->zero(prism::DeviceArray::lights);
    // Out of range is an error naming the array.
    std::string message = error_of([&] { backend->read(prism::DeviceArray::texels, back.data(), 8, data.size() * 4 - 4); });
    EXPECT_NE(message.find("'texels'"), std::string::npos) << message;
}

TEST(OpenclBackend, OversizedBuffersAreRefusedWithTheLimit) {
    REQUIRE_POCL();
    auto backend = prism::create_backend(prism::test::test_device("opencl"));
    prism::BackendInfo info = backend->info();
    std::string message = error_of([&] { backend->allocate(prism::DeviceArray::rays, info.max_buffer + 1); });
    EXPECT_NE(message.find("buffer 'rays'"), std::string::npos) << message;
    EXPECT_NE(message.find("CL_DEVICE_MAX_MEM_ALLOC_SIZE"), std::string::npos) << message;
    // The total over all arrays is checked against global memory (or PRISM_DEVICE_MEMORY_LIMIT, which the CUDA
    // backend reads too) before anything is allocated.
    ScopedEnv limit("PRISM_DEVICE_MEMORY_LIMIT", std::to_string(1 << 20));
    backend = prism::create_backend(prism::test::test_device("opencl"));
    backend->allocate(prism::DeviceArray::rays, 400 << 10);
    backend->allocate(prism::DeviceArray::hits, 400 << 10);
    message = error_of([&] { backend->allocate(prism::DeviceArray::accum, 400 << 10); });
    EXPECT_NE(message.find("buffer 'accum'"), std::string::npos) << message;
    EXPECT_NE(message.find("PRISM_DEVICE_MEMORY_LIMIT=1048576"), std::string::npos) << message;
    // Reallocating an array releases its old size: shrinking two makes room for the third.
    backend->allocate(prism::DeviceArray::rays, 64);
    backend->allocate(prism::DeviceArray::hits, 64);
    EXPECT_EQ(error_of([&] { backend->allocate(prism::DeviceArray::accum, 400 << 10); }), "");
    // A bad limit is a user error.
    ScopedEnv bad("PRISM_DEVICE_MEMORY_LIMIT", "lots");
    message = error_of([] { prism::create_backend(prism::test::test_device("opencl")); });
    EXPECT_NE(message.find("PRISM_DEVICE_MEMORY_LIMIT='lots'"), std::string::npos) << message;
}

// generate + resolve on an empty frame: primary rays equal the C++ compilation of the same function, the image is
// black, and finish() returns one device timing per launch.
TEST(OpenclBackend, GenerateAndResolveRunTheSharedKernels) {
    REQUIRE_POCL();
    auto backend = prism::create_backend(prism::test::test_device("opencl"));
    const uint32_t width = 37, height = 23, pixels = width * height;   // not a multiple of the work-group size
    FrameParams frame{};
    frame.camera_position = float4{1.0f, 2.0f, 3.0f, 0.5f};
    frame.camera_forward = float4{0.0f, 0.0f, -1.0f, float(width) / float(height)};
    frame.camera_right = float4{1.0f, 0.0f, 0.0f, 0.0f};
    frame.camera_up = float4{0.0f, 1.0f, 0.0f, 0.0f};
    frame.size = uint4{width, height, 1, 0};
    frame.env = uint4{0, 0, pixels, pixels};
    frame.tile = uint4{0, 0, width, height};
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
        ASSERT_EQ(rays[i].info.x, i);
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

namespace {

struct Case {
    std::string scene;
    uint32_t width, height, depth;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }
class OpenclAgreement : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(OpenclAgreement, PoclImageMatchesReference) {
    REQUIRE_POCL();
    const Case& c = GetParam();
    prism::Scene scene;
    prism::DeviceScene device = load(c.scene, &scene);
    prism::RenderSettings settings;
    settings.width = c.width;
    settings.height = c.height;
    settings.max_depth = c.depth;
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
    prism::RenderEngine engine(prism::test::test_device("opencl"), device);
    prism::FrameResult actual = engine.render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    prism::test::expect_ray_counts_near(expected.stats, actual.stats);
    // Device timings for every launch: generate, 4 per depth, resolve.
    EXPECT_EQ(actual.stats.stages.size(), 2u + 4u * std::min(c.depth, RT_MAX_DEPTH));
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10) << "the scene should be visible";
}

INSTANTIATE_TEST_SUITE_P(Scenes, OpenclAgreement,
                         ::testing::Values(Case{"builtin:sphere", 160, 120, 6}, Case{"builtin:bunny", 160, 120, 5},
                                           Case{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 128, 128, 6},
                                           Case{"gltf/TransmissionTest/TransmissionTest.glb", 128, 96, 6},
                                           Case{"gltf/BoxTextured/BoxTextured.glb", 96, 96, 4}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             std::string name = info.param.scene.substr(info.param.scene.find_last_of(":/") + 1);
                             for (char& ch : name)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return name;
                         });

// The GPU kernels are built without the wide traversal (kernels/traverse.h): a wide scene is refused in one line,
// before any device is opened.
TEST(OpenclAgreementMisc, WideLayoutIsRefusedInOneLine) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene, prism::BvhLayout::Wide);
    try {
        prism::RenderEngine engine("opencl:pocl", device);
        ADD_FAILURE() << "a wide scene was accepted";
    } catch (const prism::Error& e) {
        EXPECT_STREQ(e.what(), "opencl:pocl: the wide BVH layout is traced by the cpu backends only; use --bvh-layout stack, escape or auto");
    }
}

TEST(OpenclAgreementMisc, RenderingIsDeterministic) {
    REQUIRE_POCL();
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene);
    prism::RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    settings.max_depth = 6;
    prism::RenderEngine engine(prism::test::test_device("opencl"), device);
    settings.read_radiance = true;
    prism::FrameResult a = engine.render(scene.camera, settings);
    prism::FrameResult b = prism::RenderEngine(prism::test::test_device("opencl"), device).render(scene.camera, settings);
    EXPECT_EQ(a.image, b.image);
    ASSERT_FALSE(a.radiance.empty());
    EXPECT_EQ(a.radiance, b.radiance);
    EXPECT_EQ(a.image, engine.render(scene.camera, settings).image);
}

// A tiny initial queue makes the renderer regrow it on this backend too: nothing may be lost.
TEST(OpenclAgreementMisc, OverflowingQueuesAreGrownNotDropped) {
    REQUIRE_POCL();
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene);
    prism::RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.max_depth = 6;
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
    settings.queue_factor = 1.0f;
    prism::FrameResult actual = prism::RenderEngine(prism::test::test_device("opencl"), device).render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    prism::test::expect_ray_counts_near(expected.stats, actual.stats);
}

// Random rays through and around the scene: the same primitive (or both miss), t within 1e-4 relative, traced by
// the OpenCL C build of the traversal.
TEST(OpenclAgreementMisc, RayQueriesMatchReference) {
    REQUIRE_POCL();
    for (const char* spec : {"builtin:bunny", "gltf/GlassVaseFlowers/GlassVaseFlowers.glb"}) {
        SCOPED_TRACE(spec);
        prism::DeviceScene device = load(spec, nullptr);
        prism::Aabb bounds = prism::node_bounds(device.top_level.nodes[0]);   // the world box, whatever the layout
        glm::vec3 lower = bounds.lower, upper = bounds.upper;
        glm::vec3 center = 0.5f * (lower + upper);
        float radius = 0.75f * glm::length(upper - lower) + 1e-3f;
        std::mt19937 rng(20261124);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        auto in_box = [&] { return lower + (upper - lower) * glm::vec3(unit(rng), unit(rng), unit(rng)); };
        auto on_sphere = [&] {
            float z = 2.0f * unit(rng) - 1.0f, phi = 6.2831853f * unit(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
            return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
        };
        const size_t count = 20000;
        std::vector<prism::RayQuery> rays(count);
        for (size_t i = 0; i < count; ++i) {
            // Two thirds from outside towards a point of the scene box, one third from inside in any direction.
            glm::vec3 origin = i % 3 ? center + radius * on_sphere() : in_box();
            glm::vec3 direction = i % 3 ? glm::normalize(in_box() - origin) : on_sphere();
            rays[i] = prism::RayQuery{{origin.x, origin.y, origin.z}, 0.0f, {direction.x, direction.y, direction.z},
                                      INFINITY};
        }
        std::vector<prism::RayHit> expected = prism::RenderEngine("cpu-ref", device).trace(rays, false);
        std::vector<prism::RayHit> actual = prism::RenderEngine(prism::test::test_device("opencl"), device).trace(rays, false);
        ASSERT_EQ(actual.size(), count);
        size_t same = 0, hits = 0;
        for (size_t i = 0; i < count; ++i) {
            const prism::RayHit &e = expected[i], &a = actual[i];
            hits += e.t < INFINITY;
            bool both_miss = !(e.t < INFINITY) && !(a.t < INFINITY);
            bool same_hit = e.t < INFINITY && a.instance == e.instance && a.primitive == e.primitive &&
                            std::fabs(a.t - e.t) <= 1e-4f * std::fabs(e.t);
            same += both_miss || same_hit;
        }
        EXPECT_GE(double(same), 0.9999 * double(count)) << same << " of " << count << " agree";
        EXPECT_GT(hits, count / 10) << "the rays should hit the scene";
    }
}

#endif  // PRISM_HAVE_OPENCL
