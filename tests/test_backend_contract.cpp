// What every backend promises (core/render/backend.h), tested once over all the backends this machine runs (cpu, cuda,
// and the OpenCL and Vulkan test devices: PoCL and lavapipe here, $PRISM_TEST_*_DEVICE on a GPU machine): memory
// round trips with range checks; the memory budget (PRISM_DEVICE_MEMORY_LIMIT on every GPU API); every stage of
// kernels/stage_list.h run and timed in frame order; bit-identical repeat frames; queues that overflow grown, not
// dropped; ray queries against cpu-ref's hits; images against cpu-ref on real scenes; the wide layout refused in one
// line. (test_tiles.cpp's TileAgreement is the other suite over every backend.) Per-API files
// (test_cuda_backend.cpp, ...) keep only what is particular to one API.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "core/render/device_array_book.h"
#include "core/render/device_memory_limit.h"
#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "tests/test_support.h"

namespace {

using prism::DeviceArray;
using prism::test::error_message;
using prism::test::ScopedEnv;

TEST(DeviceArrayBook, BudgetCountsEveryArrayAndAReallocationFreesTheOld) {
    prism::DeviceArrayBook book("gpu", "Test Device", size_t(1) << 20);
    book.check_fits(DeviceArray::rays, 400 << 10, 400 << 10);
    book.record(DeviceArray::rays, 400 << 10, 400 << 10);
    book.record(DeviceArray::hits, 400 << 10, 400 << 10);
    std::string message = error_message([&] { book.check_fits(DeviceArray::accum, 300 << 10, 300 << 10); });
    EXPECT_EQ(message.rfind("gpu: buffer 'accum' needs 0.3 MiB, bringing the total to 1.1 MiB, above the 1.0 MiB "
                            "of memory of Test Device",
                            0),
              0u)
        << message;
    // The array's own old size does not count against it.
    EXPECT_EQ(error_message([&] { book.check_fits(DeviceArray::rays, 600 << 10, 600 << 10); }),
              "(no prism::Error thrown)");
    book.forget(DeviceArray::hits);
    EXPECT_EQ(error_message([&] { book.check_fits(DeviceArray::accum, 600 << 10, 600 << 10); }),
              "(no prism::Error thrown)");
}

TEST(DeviceArrayBook, LimitVariableSetsTheBudgetAndIsNamed) {
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "1048576");
        EXPECT_EQ(prism::device_memory_limit(), std::optional<size_t>(1048576));
        prism::DeviceArrayBook book("gpu", "Big Device", size_t(1) << 34);
        EXPECT_EQ(book.budget(), 1048576u);
        std::string message = error_message([&] { book.check_fits(DeviceArray::rays, 2 << 20, 2 << 20); });
        EXPECT_NE(message.find("allowed on Big Device (PRISM_DEVICE_MEMORY_LIMIT=1048576)"), std::string::npos)
            << message;
        // A limit above the device's memory leaves the device's memory as the budget.
        EXPECT_EQ(prism::DeviceArrayBook("gpu", "Small", 1000).budget(), 1000u);
    }
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "12 MiB");
        EXPECT_NE(error_message([] { prism::DeviceArrayBook("gpu", "d", 1 << 30); }).find("PRISM_DEVICE_MEMORY_LIMIT"),
                  std::string::npos);
    }
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "");
        EXPECT_EQ(prism::device_memory_limit(), std::nullopt);
    }
    // Without device memory (the cpu backend) there is no budget, whatever the variable says.
    ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "16");
    EXPECT_EQ(prism::DeviceArrayBook("cpu", "", std::nullopt).budget(), SIZE_MAX);
}

TEST(DeviceArrayBook, RangesAreCheckedAgainstTheAllocatedSize) {
    prism::DeviceArrayBook book("gpu", "d", std::nullopt);
    EXPECT_EQ(error_message([&] { book.check_range(DeviceArray::texels, 0, 0); }),
              "gpu: access past the end of array 'texels' (0+0 of 0 bytes)");  // never allocated
    book.record(DeviceArray::texels, 100, 112);
    book.check_range(DeviceArray::texels, 100, 0);
    book.check_range(DeviceArray::texels, 0, 100);
    EXPECT_EQ(error_message([&] { book.check_range(DeviceArray::texels, 8, 96); }),
              "gpu: access past the end of array 'texels' (96+8 of 100 bytes)");
    EXPECT_NE(error_message([&] { book.check_range(DeviceArray::texels, SIZE_MAX, 8); }), "(no prism::Error thrown)");
}

// The backends every suite here runs on.
const std::vector<std::string>& backend_specs() {
    static const std::vector<std::string> specs = {"cpu", "cuda", prism::test::test_device("opencl"),
                                                   prism::test::test_device("vulkan")};
    return specs;
}

std::string api_of(const std::string& spec) { return prism::parse_backend_spec(spec).api; }

// Scenes are loaded once per process and layout: several suites and backends render the same ones.
struct LoadedScene {
    prism::Scene scene;
    prism::DeviceScene device;
};
const LoadedScene& loaded(const std::string& spec, const std::string& backend) {
    static std::map<std::pair<std::string, prism::BvhLayout>, std::unique_ptr<LoadedScene>> cache;
    prism::BvhLayout layout = prism::resolve_bvh_layout("auto", backend);
    std::unique_ptr<LoadedScene>& entry = cache[{spec, layout}];
    if (!entry) {  // kept only once loaded: a load that throws (a missing file) leaves no empty scene behind
        auto scene = std::make_unique<LoadedScene>();
        scene->device = prism::test::load_device_scene(spec, &scene->scene, layout);
        entry = std::move(scene);
    }
    return *entry;
}

// A test of one backend: skipped where it does not run; Vulkan under the validation layer, whose every message
// fails the test.
template <typename Param>
class OnBackend : public ::testing::TestWithParam<Param> {
protected:
    virtual const std::string& backend() const = 0;
    void SetUp() override {
        std::string reason;
        if (!prism::test::backend_spec_runs_here(backend(), &reason)) GTEST_SKIP() << reason;
        prism::test::begin_backend_checks(backend());
    }
    void TearDown() override {
        if (this->IsSkipped()) return;
        std::vector<std::string> messages = prism::test::backend_check_messages(backend());
        EXPECT_TRUE(messages.empty()) << messages.size() << " validation/driver message(s), the first: "
                                      << (messages.empty() ? "" : messages.front());
    }
    const LoadedScene& scene(const std::string& spec) const { return loaded(spec, backend()); }
};

class BackendContract : public OnBackend<std::string> {
protected:
    const std::string& backend() const override { return GetParam(); }
};

// Whole arrays, a part at an offset and zeroing round-trip; larger than one Vulkan staging piece (64 MiB), so the
// chunked copies run. Zero-size arrays are legal (a scene without textures); reads and writes past the end, or of
// an array never allocated, are errors naming the API and the array.
TEST_P(BackendContract, MemoryRoundTripsAndRangesAreChecked) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(GetParam());
    EXPECT_EQ(backend->info().name, api_of(GetParam()));
    std::vector<uint32_t> data((80u << 20) / 4);
    for (size_t i = 0; i < data.size(); ++i) data[i] = uint32_t(i * 2654435761u);
    backend->allocate(DeviceArray::texels, data.size() * 4);
    backend->write(DeviceArray::texels, data.data(), data.size() * 4);
    std::vector<uint32_t> back(data.size());
    backend->read(DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_TRUE(back == data);
    uint32_t part[3] = {1, 2, 3};
    backend->write(DeviceArray::texels, part, sizeof part, 40);
    uint32_t window[5];
    backend->read(DeviceArray::texels, window, sizeof window, 36);
    EXPECT_EQ(window[0], data[9]);
    EXPECT_EQ(window[1], 1u);
    EXPECT_EQ(window[3], 3u);
    EXPECT_EQ(window[4], data[13]);
    backend->zero(DeviceArray::texels);
    backend->read(DeviceArray::texels, window, sizeof window, 36);
    for (uint32_t w : window) EXPECT_EQ(w, 0u);

    backend->allocate(DeviceArray::lights, 0);
    backend->write(DeviceArray::lights, nullptr, 0);
    backend->zero(DeviceArray::lights);

    std::string past = error_message([&] { backend->read(DeviceArray::texels, window, 8, data.size() * 4 - 4); });
    EXPECT_EQ(past.rfind(api_of(GetParam()) + ": access past the end of array 'texels'", 0), 0u) << past;
    std::string never = error_message([&] { backend->read(DeviceArray::rays, window, 4); });
    EXPECT_NE(never.find("'rays'"), std::string::npos) << never;
}

// A write takes the caller's data when it is called: the caller may overwrite or free its memory at once, and
// writes land in the order made (small ones, which a backend may copy and enqueue without waiting, and large ones).
TEST_P(BackendContract, WritesTakeTheCallersDataWhenCalled) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(GetParam());
    const size_t small = 1024, large = (3u << 20) / 4;
    backend->allocate(DeviceArray::counters, small * 4);
    backend->allocate(DeviceArray::texels, large * 4);
    for (uint32_t round = 1; round <= 8; ++round) {
        auto data = std::make_unique<std::vector<uint32_t>>(large, round);
        backend->write(DeviceArray::counters, data->data(), small * 4);
        if (round % 3 == 0) backend->write(DeviceArray::texels, data->data(), large * 4);
        std::fill(data->begin(), data->end(), 0xdeadbeefu);
        data.reset();
    }
    std::vector<uint32_t> counters(small), texels(large);
    backend->read(DeviceArray::counters, counters.data(), small * 4);
    backend->read(DeviceArray::texels, texels.data(), large * 4);
    EXPECT_TRUE(std::all_of(counters.begin(), counters.end(), [](uint32_t w) { return w == 8u; }));
    EXPECT_TRUE(std::all_of(texels.begin(), texels.end(), [](uint32_t w) { return w == 6u; }));
}

// read_pinned (how a frame's image comes back): the array's contents as of the call, a smaller read within the
// same host memory, a larger one after growing it, each read seeing writes made since; ranges checked as read's.
TEST_P(BackendContract, PinnedReadsSeeTheArrayAsItIsNow) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(GetParam());
    std::vector<uint32_t> data(1u << 20);
    for (size_t i = 0; i < data.size(); ++i) data[i] = uint32_t(i * 2654435761u);
    backend->allocate(DeviceArray::image, data.size() * 4);
    backend->write(DeviceArray::image, data.data(), data.size() * 4);
    const auto* small = static_cast<const uint32_t*>(backend->read_pinned(DeviceArray::image, 4096));
    ASSERT_NE(small, nullptr);
    EXPECT_TRUE(std::equal(small, small + 1024, data.begin()));
    for (size_t i = 0; i < data.size(); ++i) data[i] = ~data[i];
    backend->write(DeviceArray::image, data.data(), data.size() * 4);
    const auto* whole = static_cast<const uint32_t*>(backend->read_pinned(DeviceArray::image, data.size() * 4));
    ASSERT_NE(whole, nullptr);
    EXPECT_TRUE(std::equal(whole, whole + data.size(), data.begin()));
    backend->zero(DeviceArray::image);
    const auto* zeroed = static_cast<const uint32_t*>(backend->read_pinned(DeviceArray::image, 4096));
    EXPECT_TRUE(std::all_of(zeroed, zeroed + 1024, [](uint32_t w) { return w == 0u; }));
    std::string past = error_message([&] { backend->read_pinned(DeviceArray::image, data.size() * 4 + 4); });
    EXPECT_EQ(past.rfind(api_of(GetParam()) + ": access past the end of array 'image'", 0), 0u) << past;
}

// PRISM_DEVICE_MEMORY_LIMIT caps what all arrays take together on every GPU API, before anything is allocated,
// and the error names the array and the limit; shrinking arrays makes room again.
TEST_P(BackendContract, MemoryLimitCountsEveryArrayAndNamesTheLimit) {
    if (api_of(GetParam()) == "cpu") GTEST_SKIP() << "the limit is for GPU memory";
    ScopedEnv limit("PRISM_DEVICE_MEMORY_LIMIT", std::to_string(1 << 20));
    std::unique_ptr<prism::Backend> backend = prism::create_backend(GetParam());
    backend->allocate(DeviceArray::rays, 400 << 10);
    backend->allocate(DeviceArray::hits, 400 << 10);
    std::string message = error_message([&] { backend->allocate(DeviceArray::accum, 400 << 10); });
    EXPECT_EQ(message.rfind(api_of(GetParam()) + ": buffer 'accum' needs", 0), 0u) << message;
    EXPECT_NE(message.find("(PRISM_DEVICE_MEMORY_LIMIT=1048576)"), std::string::npos) << message;
    backend->allocate(DeviceArray::rays, 64);
    backend->allocate(DeviceArray::hits, 64);
    EXPECT_EQ(error_message([&] { backend->allocate(DeviceArray::accum, 400 << 10); }), "(no prism::Error thrown)");
    // A whole frame that needs more than the limit stops with the same error, not a crash or a partial image.
    const LoadedScene& s = scene("builtin:sphere");
    std::string frame = error_message([&] {
        prism::RenderEngine(GetParam(), s.device).render(s.scene.camera, prism::test::small_settings(640, 480, 4));
    });
    EXPECT_NE(frame.find("PRISM_DEVICE_MEMORY_LIMIT"), std::string::npos) << frame;
    // A limit that is not a byte count stops the backend's creation.
    ScopedEnv bad("PRISM_DEVICE_MEMORY_LIMIT", "lots");
    std::string refused = error_message([&] { prism::create_backend(GetParam()); });
    EXPECT_NE(refused.find("PRISM_DEVICE_MEMORY_LIMIT='lots'"), std::string::npos) << refused;
}

// The frame loop runs every line of the stage list, in list order within its pass, each once per depth for the
// bounce stages, and every backend times each launch: a stage added to the list reaches every backend.
TEST_P(BackendContract, EveryStageOfTheListRunsAndIsTimedInFrameOrder) {
    const LoadedScene& s = scene("builtin:sphere");
    prism::RenderSettings settings = prism::test::small_settings(32, 24, 3);
    prism::FrameResult frame = prism::RenderEngine(GetParam(), s.device).render(s.scene.camera, settings);

    // The sphere has no cut-out or blended material: its frames launch every stage but those that need a flag
    // (shadow_layers: RT_FLAG_ALPHA_SHADOWS; Backends/EveryBackend.ShadowRaysPassCutOutsAndBlendedSurfaces runs that
    // one on every backend).
    const uint32_t flags = 0;
    std::vector<std::pair<prism::Stage, uint32_t>> expected;
    auto pass = [&](prism::StagePass which, uint32_t depth) {
        for (size_t stage = 0; stage < prism::stage_count; ++stage)
            if (prism::stage_pass(prism::Stage(stage)) == which && prism::stage_runs(prism::Stage(stage), flags))
                expected.emplace_back(prism::Stage(stage), depth);
    };
    pass(prism::StagePass::Before, 0);
    for (uint32_t depth = 0; depth < settings.max_depth; ++depth) pass(prism::StagePass::Bounce, depth);
    pass(prism::StagePass::After, 0);

    ASSERT_EQ(frame.stats.stages.size(), expected.size());
    double total = 0.0;
    for (size_t i = 0; i < expected.size(); ++i) {
        const prism::StageTiming& t = frame.stats.stages[i];
        EXPECT_EQ(t.stage, expected[i].first) << "launch " << i << ": " << prism::stage_name(t.stage);
        EXPECT_EQ(t.depth, expected[i].second) << "launch " << i << ": " << prism::stage_name(t.stage);
        EXPECT_TRUE(t.milliseconds >= 0.0 && t.milliseconds < 1e6) << "a wrapped counter? " << t.milliseconds;
        total += t.milliseconds;
    }
    EXPECT_GT(total, 0.0);
}

// What each stage's kernel got from its API's compiler, where the API says: every stage of the list once, in list
// order. CUDA's registers are ptxas's, and the traversal stages stay within the 64 that their launch bounds ask for
// (8 blocks of 128 on an SM, backends/cuda/stages.cu); OpenCL reports private memory but no registers.
TEST_P(BackendContract, KernelResourcesNameEveryStage) {
    const LoadedScene& s = scene("builtin:sphere");
    prism::RenderEngine engine(GetParam(), s.device);
    prism::KernelResources resources = engine.kernel_resources();
    EXPECT_FALSE(resources.source.empty());
    const std::string api = api_of(GetParam());
    if (api == "cpu" || (api == "vulkan" && resources.stages.empty())) {
        EXPECT_TRUE(resources.stages.empty());
        if (api == "vulkan") {
            EXPECT_NE(resources.source.find("lacks VK_KHR_pipeline_executable_properties"), std::string::npos)
                << resources.source;
        }
        return;
    }
    ASSERT_EQ(resources.stages.size(), prism::stage_count) << resources.source;
    for (size_t i = 0; i < prism::stage_count; ++i) {
        const prism::StageResources& stage = resources.stages[i];
        SCOPED_TRACE(prism::stage_name(stage.stage));
        EXPECT_EQ(stage.stage, prism::Stage(i));
        if (api == "cuda") {
            EXPECT_GT(stage.registers, 0);
            EXPECT_LE(stage.registers, 255);
            EXPECT_GE(stage.private_bytes, 0);
            std::string name = prism::stage_name(stage.stage);
            if (name == "intersect" || name == "occlude" || name == "shadow") {
                EXPECT_LE(stage.registers, 64);
            }
        }
        if (api == "opencl") {
            EXPECT_EQ(stage.registers, -1);
            EXPECT_GE(stage.private_bytes, 0);
            EXPECT_GE(stage.shared_bytes, 0);
        }
        if (api == "vulkan") {
            EXPECT_FALSE(stage.statistics.empty());
        }
    }
}

// Exact fixed-point accumulation and deterministic BVHs: the same frame twice, or on a second instance of the
// backend, is the same to the bit (image and radiance).
TEST_P(BackendContract, RendersAreBitIdentical) {
    const LoadedScene& s = scene("builtin:sphere");
    prism::RenderSettings settings = prism::test::small_settings(96, 72, 6);
    settings.read_radiance = true;
    prism::RenderEngine engine(GetParam(), s.device);
    prism::FrameResult a = engine.render(s.scene.camera, settings);
    prism::FrameResult b = engine.render(s.scene.camera, settings);
    prism::FrameResult c = prism::RenderEngine(GetParam(), s.device).render(s.scene.camera, settings);
    EXPECT_EQ(a.image, b.image);
    ASSERT_FALSE(a.radiance.empty());
    EXPECT_EQ(a.radiance, b.radiance);
    EXPECT_EQ(a.image, c.image);
}

// A tiny first queue makes the renderer grow it and render again: nothing is lost, and the grown size is kept.
TEST_P(BackendContract, OverflowingQueuesAreGrownNotDropped) {
    const LoadedScene& s = scene("builtin:sphere");
    prism::RenderSettings settings = prism::test::small_settings(64, 48, 6);
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", s.device).render(s.scene.camera, settings);
    settings.queue_factor = 1.0f;
    prism::RenderEngine engine(GetParam(), s.device);
    prism::FrameResult actual = engine.render(s.scene.camera, settings);
    EXPECT_GT(actual.stats.regrows, 0u) << "this frame needs more than one ray per pixel at some depth";
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    prism::test::expect_ray_counts_near(expected.stats, actual.stats);
    EXPECT_EQ(engine.render(s.scene.camera, settings).stats.regrows, 0u);
}

// Random rays through and around the scene: the same instance and primitive as cpu-ref's (or both miss), t within
// 1e-4 relative, on 99.99% of them; any-hit queries blocked or not alike. The PLY is one instance: in the stack
// layout its rays go through the one-mesh stages (intersect_mesh, occlude_mesh).
TEST_P(BackendContract, RayQueriesMatchTheReferenceHits) {
    for (const char* spec : {"builtin:bunny", "gltf/GlassVaseFlowers/GlassVaseFlowers.glb", "stanford/bunny.ply"}) {
        SCOPED_TRACE(spec);
        const prism::DeviceScene& device = scene(spec).device;
        prism::Aabb bounds = prism::node_bounds(device.top_level.nodes[0]);  // the world box, whatever the layout
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
            rays[i] = prism::RayQuery{
                {origin.x, origin.y, origin.z}, 0.0f, {direction.x, direction.y, direction.z}, INFINITY};
        }
        prism::RenderEngine reference("cpu-ref", device), engine(GetParam(), device);
        std::vector<prism::RayHit> expected = reference.trace(rays, false), actual = engine.trace(rays, false);
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

        // Launches back to back on rays uploaded once (`prism rays --bench`'s timing) find the same hits, and
        // each launch has its own time.
        std::vector<prism::RayHit> again = engine.trace(rays, false, 3);
        ASSERT_EQ(again.size(), count);
        ASSERT_EQ(engine.last_launch_ms().size(), 3u);
        for (double ms : engine.last_launch_ms()) EXPECT_GE(ms, 0.0);
        size_t repeated = 0;
        for (size_t i = 0; i < count; ++i)
            repeated += again[i].instance == actual[i].instance && again[i].primitive == actual[i].primitive &&
                        (again[i].t == actual[i].t || !(actual[i].t < INFINITY));
        EXPECT_EQ(repeated, count);

        std::vector<prism::RayHit> expected_any = reference.trace(rays, true), actual_any = engine.trace(rays, true);
        size_t same_any = 0;
        for (size_t i = 0; i < count; ++i) same_any += (expected_any[i].t < INFINITY) == (actual_any[i].t < INFINITY);
        EXPECT_GE(double(same_any), 0.9999 * double(count));
    }
}

// A mesh an animation deforms (Khronos' SimpleSkin, its joints turning): RenderEngine::move_to poses it, refits
// its BVH and uploads the arrays again; the frame is the one cpu-ref draws from a scene built in that pose.
TEST_P(BackendContract, APosedMeshIsTracedWhereItMoved) {
    const prism::Scene& loaded_scene = scene("gltf/SimpleSkin/SimpleSkin.gltf").scene;
    prism::BvhBuildOptions options;
    options.layout = prism::resolve_bvh_layout("auto", backend());
    prism::DeviceScene device = prism::build_device_scene(loaded_scene, options);
    prism::RenderEngine engine(backend(), device);
    const prism::RenderSettings settings = prism::test::small_settings(64, 48, 3);
    const prism::FrameResult still = engine.render(loaded_scene.camera, settings);
    auto pixels_differing = [](const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
        size_t n = 0;
        for (size_t i = 0; i < a.size() && i < b.size(); ++i) n += a[i] != b[i];
        return n;
    };
    // The mesh bent a quarter turn one way (at 1 s) and the other (at 4 s), and on its way back (at 1.75 s).
    for (double seconds : {1.0, 1.75, 4.0}) {
        SCOPED_TRACE(seconds);
        engine.move_to(loaded_scene, device, seconds);
        const prism::FrameResult moved = engine.render(loaded_scene.camera, settings);
        const prism::Scene posed = prism::test::scene_posed_at(loaded_scene, seconds);
        const prism::FrameResult expected =
            prism::RenderEngine("cpu-ref", prism::build_device_scene(posed, options)).render(posed.camera, settings);
        EXPECT_GE(prism::test::psnr_rgba8(expected.image, moved.image), 45.0);
        EXPECT_GT(pixels_differing(still.image, moved.image), still.image.size() / 50);  // it did move
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendContract, ::testing::ValuesIn(backend_specs()),
                         [](const auto& info) { return prism::test::test_name_of(info.param); });

// The GPU kernels are built without the wide traversal (kernels/traverse.h): a wide scene is refused in one line,
// before any device is opened (so this runs without one).
class GpuBackend : public ::testing::TestWithParam<std::string> {};

TEST_P(GpuBackend, WideLayoutIsRefusedInOneLine) {
    prism::Scene scene;
    prism::DeviceScene device = prism::test::load_device_scene("builtin:sphere", &scene, prism::BvhLayout::Wide);
    EXPECT_EQ(error_message([&] { prism::RenderEngine engine(GetParam(), device); }),
              GetParam() +
                  ": the wide BVH layout is traced by the cpu backends only; use --bvh-layout stack, escape "
                  "or auto");
}

INSTANTIATE_TEST_SUITE_P(Backends, GpuBackend,
                         ::testing::Values("cuda", prism::test::test_device("opencl"),
                                           prism::test::test_device("vulkan")),
                         [](const auto& info) { return prism::test::test_name_of(info.param); });

// Images against the cpu-ref oracle on the seed's scenes and glTF models with glass, transmission and textures:
// PSNR >= 50 dB, every depth tracing what the oracle traced up to rounding (GPU float math, FMA contraction and
// division precision, may tip a grazing ray or light the other way: expect_ray_counts_near), and the scene visible.
struct AgreementCase {
    std::string scene;
    uint32_t width, height, depth;
    float exposure = 0.0f;  // the resolve stage's display transform (kernels/display.h)
    prism::ToneMap tone_map = prism::ToneMap::None;
};
void PrintTo(const AgreementCase& c, std::ostream* os) { *os << c.scene; }

class Agreement : public OnBackend<std::tuple<std::string, AgreementCase>> {
protected:
    const std::string& backend() const override { return std::get<0>(GetParam()); }
};

TEST_P(Agreement, ImageMatchesReference) {
    const AgreementCase& c = std::get<1>(GetParam());
    const LoadedScene& s = scene(c.scene);
    prism::RenderSettings settings = prism::test::small_settings(c.width, c.height, c.depth);
    settings.exposure = c.exposure;
    settings.tone_map = c.tone_map;
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", s.device).render(s.scene.camera, settings);
    prism::FrameResult actual = prism::RenderEngine(backend(), s.device).render(s.scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    prism::test::expect_ray_counts_near(expected.stats, actual.stats);
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10) << "the scene should be visible";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, Agreement,
    ::testing::Combine(
        ::testing::ValuesIn(backend_specs()),
        ::testing::Values(AgreementCase{"builtin:sphere", 96, 72, 6},
                          // Two stops brighter through the tone map: the resolve stage's display transform.
                          AgreementCase{"builtin:sphere", 96, 72, 6, 2.0f, prism::ToneMap::Neutral},
                          AgreementCase{"builtin:bunny", 96, 72, 5}, AgreementCase{"builtin:dragon", 96, 72, 4},
                          AgreementCase{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 96, 96, 6},
                          AgreementCase{"gltf/TransmissionTest/TransmissionTest.glb", 96, 72, 6},
                          AgreementCase{"gltf/BoxTextured/BoxTextured.glb", 64, 64, 4},
                          // Thin films: cos and exp in the shade stage (kernels/iridescence.h).
                          AgreementCase{"gltf/IridescenceSuzanne/IridescenceSuzanne.glb", 128, 48, 5},
                          // Coplanar overlapping trim: the tie rule of kernels/traverse.h.
                          AgreementCase{"mcguire/conference/conference.obj", 160, 120, 4},
                          // Spot lights' cones and a point light's range (rt_shadow_ray, kernels/shade.h).
                          AgreementCase{"examples/spot-lights.json", 96, 72, 5},
                          // Small spheres far from the camera: the edge slack of kernels/intersect.h.
                          AgreementCase{"gltf/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.glb", 160, 120,
                                        6})),
    [](const auto& info) {
        const AgreementCase& c = std::get<1>(info.param);
        const std::string tone_mapped = c.tone_map == prism::ToneMap::Neutral ? "_tone_mapped" : "";
        return prism::test::test_name_of(std::get<0>(info.param) + "_" +
                                         c.scene.substr(c.scene.find_last_of(":/") + 1) + tone_mapped);
    });

}  // namespace
