// The `cuda` backend. Without a CUDA device (this development machine, CI) every device test skips with the
// reason probe() gives, and the no-device tests check that asking for CUDA is a clean prism::Error, not a crash.
// With a device (the H100 machine): images agree with cpu-ref, ray queries agree with cpu-ref's hits, frames are
// bit-identical run to run, and PRISM_DEVICE_MEMORY_LIMIT produces the out-of-memory error.
#ifdef PRISM_HAVE_CUDA

#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "backends/cuda/cuda_backend.h"
#include "core/error.h"
#include "core/render_engine.h"
#include "core/scene_loader.h"
#include "tests/test_support.h"

namespace {

#define REQUIRE_CUDA_DEVICE()                                                                  \
    do {                                                                                       \
        std::string reason_;                                                                   \
        /* probe()'s detail reads "no CUDA device (cudaGetDeviceCount: ...)" */               \
        if (!prism::test::backend_available("cuda", &reason_)) GTEST_SKIP() << reason_;        \
    } while (0)

using prism::test::ScopedEnv;

std::string resolve(const std::string& spec) {
    return spec.rfind("builtin:", 0) == 0 ? spec : prism::test::scene(spec).string();
}

struct LoadedScene {
    prism::Scene scene;
    prism::DeviceScene device;
};

// The BVH layout is the one the renderer would pick for this backend: stack, or $PRISM_BVH_LAYOUT (so the whole
// suite can run on another layout); the tests that name a layout pass it.
LoadedScene load(const std::string& spec, prism::BvhLayout layout = prism::resolve_bvh_layout("auto", "cuda")) {
    prism::LoadOptions options;
    options.data_dir = prism::test::scenes_dir();
    LoadedScene loaded;
    loaded.scene = prism::load_scene(resolve(spec), options);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    loaded.device = prism::build_device_scene(loaded.scene, bvh);
    return loaded;
}

prism::RenderSettings small(uint32_t width, uint32_t height, uint32_t depth) {
    prism::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.max_depth = depth;
    return settings;
}

// Rays the camera sees (jittered through the view) and rays from all around the scene towards its centre.
std::vector<prism::RayQuery> query_rays(const prism::Camera& camera, size_t count, uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    glm::vec3 forward = glm::normalize(camera.target - camera.position);
    glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::vec3 up = glm::cross(right, forward);
    float distance = glm::length(camera.target - camera.position);
    std::vector<prism::RayQuery> rays(count);
    for (size_t i = 0; i < count; ++i) {
        glm::vec3 origin, direction;
        if (i % 2 == 0) {
            origin = camera.position;
            direction = forward + right * (0.6f * unit(random)) + up * (0.6f * unit(random));
        } else {
            glm::vec3 around(unit(random), unit(random), unit(random));
            if (glm::length(around) < 1e-3f) around = glm::vec3(1, 0, 0);
            origin = camera.target + glm::normalize(around) * distance;
            glm::vec3 aim = camera.target + glm::vec3(unit(random), unit(random), unit(random)) * (0.3f * distance);
            direction = aim - origin;
        }
        direction = glm::normalize(direction);
        rays[i] = prism::RayQuery{{origin.x, origin.y, origin.z}, 0.0f, {direction.x, direction.y, direction.z}, INFINITY};
    }
    return rays;
}

struct Case {
    std::string scene;
    uint32_t width, height, depth;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

class CudaAgreement : public ::testing::TestWithParam<Case> {};

}  // namespace

// ---- Runs everywhere --------------------------------------------------------------------------------------------

TEST(CudaBackend, WithoutDeviceCreationIsACleanError) {
    std::string reason;
    if (prism::test::backend_available("cuda", &reason)) GTEST_SKIP() << "a CUDA device is present: " << reason;
    EXPECT_NE(reason.find("CUDA"), std::string::npos) << reason;
    EXPECT_NE(reason.find("no CUDA device"), std::string::npos) << reason;
    for (const char* name : {"cuda", "cuda:0", "cuda:h100"}) {
        try {
            prism::create_backend(name);
            ADD_FAILURE() << name << " created without a device";
        } catch (const prism::Error& error) {
            std::string message = error.what();
            EXPECT_NE(message.find("CUDA"), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        }
    }
}

TEST(CudaBackend, ProbeReportsAvailabilityWithAReason) {
    prism::register_builtin_backends();
    const prism::BackendFactory* cuda = nullptr;
    for (const prism::BackendFactory& factory : prism::registered_backends())
        if (factory.name == "cuda") cuda = &factory;
    ASSERT_NE(cuda, nullptr) << "this build has CUDA enabled but did not register the backend";
    prism::BackendAvailability a = cuda->probe();
    EXPECT_EQ(a.name, "cuda");
    EXPECT_FALSE(a.detail.empty());
    EXPECT_EQ(a.available, !a.devices.empty());
}

TEST(CudaBackend, MemoryLimitVariableIsParsed) {
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "1048576");
        EXPECT_EQ(prism::cuda::device_memory_limit(), std::optional<size_t>(1048576));
    }
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "12 MiB");
        EXPECT_THROW(prism::cuda::device_memory_limit(), prism::Error);
    }
    {
        ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", "");
        EXPECT_EQ(prism::cuda::device_memory_limit(), std::nullopt);
    }
}

// ---- Needs a CUDA device ----------------------------------------------------------------------------------------

TEST_P(CudaAgreement, MatchesReferenceRenderer) {
    REQUIRE_CUDA_DEVICE();
    const Case& c = GetParam();
    LoadedScene s = load(c.scene);
    prism::RenderSettings settings = small(c.width, c.height, c.depth);
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", s.device).render(s.scene.camera, settings);
    prism::FrameResult actual = prism::RenderEngine("cuda", s.device).render(s.scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    // No ray dropped: the first frame fitted its queues, and every depth traced what the oracle traced.
    prism::test::expect_ray_counts_near(expected.stats, actual.stats);
    // Device timings: one per launch (generate, four stages per depth, resolve), each a real duration.
    ASSERT_EQ(actual.stats.stages.size(), 2 + 4 * size_t(c.depth));
    for (const prism::StageTiming& t : actual.stats.stages) EXPECT_TRUE(t.milliseconds >= 0.0 && std::isfinite(t.milliseconds));
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10) << "the scene should be visible";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, CudaAgreement,
    ::testing::Values(Case{"builtin:sphere", 160, 120, 6}, Case{"builtin:bunny", 160, 120, 6},
                      Case{"builtin:dragon", 128, 96, 6},
                      Case{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 128, 128, 6},
                      Case{"gltf/TransmissionTest/TransmissionTest.glb", 128, 96, 6},
                      Case{"gltf/BoxTextured/BoxTextured.glb", 96, 96, 4}),
    [](const ::testing::TestParamInfo<Case>& info) {
        std::string name = info.param.scene.substr(info.param.scene.find_last_of(":/") + 1);
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
        return name;
    });

static void expect_ray_queries_match_reference(const LoadedScene& s) {
    std::vector<prism::RayQuery> rays = query_rays(s.scene.camera, 20000, 20240611);
    std::vector<prism::RayHit> expected = prism::RenderEngine("cpu-ref", s.device).trace(rays, false);
    prism::RenderEngine cuda("cuda", s.device);
    std::vector<prism::RayHit> actual = cuda.trace(rays, false);
    ASSERT_EQ(actual.size(), expected.size());
    size_t same = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const prism::RayHit &e = expected[i], &a = actual[i];
        hits += e.t < INFINITY;
        bool both_miss = !(e.t < INFINITY) && !(a.t < INFINITY);
        bool same_hit = e.t < INFINITY && a.t < INFINITY && e.instance == a.instance && e.primitive == a.primitive &&
                        std::fabs(e.t - a.t) <= 1e-4f * std::fabs(e.t);
        same += both_miss || same_hit;
    }
    EXPECT_GE(double(same) / double(rays.size()), 0.9999) << same << " of " << rays.size() << " agree";
    EXPECT_GT(hits, rays.size() / 4) << "the rays should mostly hit the model";

    // Any-hit queries: the same rays are blocked or not.
    std::vector<prism::RayHit> expected_any = prism::RenderEngine("cpu-ref", s.device).trace(rays, true);
    std::vector<prism::RayHit> actual_any = cuda.trace(rays, true);
    size_t same_any = 0;
    for (size_t i = 0; i < rays.size(); ++i) same_any += (expected_any[i].t < INFINITY) == (actual_any[i].t < INFINITY);
    EXPECT_GE(double(same_any) / double(rays.size()), 0.9999);
}

TEST(CudaBackend, RayQueriesMatchReferenceHits) {
    REQUIRE_CUDA_DEVICE();
    expect_ray_queries_match_reference(load("builtin:bunny"));
}

// The GPU kernels are built without the wide traversal (kernels/traverse.h): a wide scene is refused in one line,
// before any device is opened (so this runs without one).
TEST(CudaBackend, WideLayoutIsRefusedInOneLine) {
    LoadedScene s = load("builtin:sphere", prism::BvhLayout::Wide);
    try {
        prism::RenderEngine engine("cuda", s.device);
        ADD_FAILURE() << "a wide scene was accepted";
    } catch (const prism::Error& e) {
        EXPECT_STREQ(e.what(), "cuda: the wide BVH layout is traced by the cpu backends only; use --bvh-layout stack, escape or auto");
    }
}

TEST(CudaBackend, RendersAreBitIdentical) {
    REQUIRE_CUDA_DEVICE();
    LoadedScene s = load("builtin:sphere");
    prism::RenderSettings settings = small(160, 120, 8);
    prism::RenderEngine engine("cuda", s.device);
    settings.read_radiance = true;
    prism::FrameResult a = engine.render(s.scene.camera, settings);
    prism::FrameResult b = engine.render(s.scene.camera, settings);
    prism::FrameResult c = prism::RenderEngine("cuda", s.device).render(s.scene.camera, settings);
    EXPECT_EQ(a.image, b.image);
    ASSERT_FALSE(a.radiance.empty());
    EXPECT_EQ(a.radiance, b.radiance);
    EXPECT_EQ(a.image, c.image);
}

TEST(CudaBackend, MemoryLimitGivesACleanError) {
    REQUIRE_CUDA_DEVICE();
    LoadedScene s = load("builtin:sphere");
    ScopedEnv env("PRISM_DEVICE_MEMORY_LIMIT", std::to_string(4u << 20));   // the scene fits, 640x480 queues do not
    try {
        prism::RenderEngine engine("cuda", s.device);
        engine.render(s.scene.camera, small(640, 480, 4));
        FAIL() << "a frame that needs more than PRISM_DEVICE_MEMORY_LIMIT rendered";
    } catch (const prism::Error& error) {
        std::string message = error.what();
        EXPECT_EQ(message.rfind("cuda: buffer '", 0), 0u) << message;
        EXPECT_NE(message.find("MiB are free on"), std::string::npos) << message;
        EXPECT_NE(message.find("PRISM_DEVICE_MEMORY_LIMIT"), std::string::npos) << message;
    }
}

TEST(CudaBackend, MemoryRoundTripAndBounds) {
    REQUIRE_CUDA_DEVICE();
    std::unique_ptr<prism::Backend> backend = prism::create_backend("cuda:0");
    prism::BackendInfo info = backend->info();
    EXPECT_EQ(info.name, "cuda");
    EXPECT_GT(info.device_memory, 0u);
    std::vector<uint32_t> data(1000);
    for (uint32_t i = 0; i < data.size(); ++i) data[i] = i * 2654435761u;
    backend->allocate(prism::DeviceArray::texels, data.size() * 4);
    backend->write(prism::DeviceArray::texels, data.data(), data.size() * 4);
    std::vector<uint32_t> back(data.size());
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_EQ(back, data);
    backend->read(prism::DeviceArray::texels, back.data(), 40, 400);   // 10 words from word 100
    EXPECT_EQ(back[0], data[100]);
    backend->zero(prism::DeviceArray::texels);
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_EQ(back, std::vector<uint32_t>(data.size(), 0u));
    EXPECT_THROW(backend->write(prism::DeviceArray::texels, data.data(), 8, data.size() * 4 - 4), prism::Error);
    EXPECT_THROW(backend->read(prism::DeviceArray::rays, back.data(), 4), prism::Error);   // never allocated
}

TEST(CudaBackend, DeviceSelection) {
    REQUIRE_CUDA_DEVICE();
    EXPECT_NO_THROW(prism::create_backend("cuda:0"));
    std::string name = prism::create_backend("cuda")->info().device;
    EXPECT_NO_THROW(prism::create_backend("cuda:" + name.substr(0, name.find(' '))));   // e.g. "cuda:NVIDIA"
    try {
        prism::create_backend("cuda:no-such-gpu");
        ADD_FAILURE() << "an unknown device name was accepted";
    } catch (const prism::Error& error) {
        EXPECT_NE(std::string(error.what()).find("no device matches 'no-such-gpu'"), std::string::npos) << error.what();
    }
    EXPECT_THROW(prism::create_backend("cuda:99"), prism::Error);
}

#endif  // PRISM_HAVE_CUDA
