// The vulkan backend on Mesa lavapipe (vulkan:llvmpipe; $PRISM_TEST_VULKAN_DEVICE picks another, e.g.
// vulkan:nvidia on the GPU machine), always with VK_LAYER_KHRONOS_validation: any warning or
// error a layer or the driver reports fails the test. Checks the GLSL side of the layout contract, agreement with
// the cpu-ref oracle (images and ray queries), determinism, timings and the errors a user can cause.
// Skipped, with the reason, where no Vulkan device (or not the chosen one) is present.
#include <gtest/gtest.h>

#ifdef PRISM_HAVE_VULKAN

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <random>
#include <sys/stat.h>

#include "backends/backend_list.h"
#include "backends/vulkan/vulkan_backend.h"
#include "core/error.h"
#include "core/render_engine.h"
#include "core/scene_loader.h"
#include "tests/test_support.h"

namespace {

// The device under test: $PRISM_TEST_VULKAN_DEVICE (e.g. "vulkan:nvidia" on the GPU machine), else lavapipe.
std::string device_spec() { return prism::test::test_device("vulkan"); }
const std::string kDevice = device_spec();
bool on_lavapipe() { return kDevice.find("llvmpipe") != std::string::npos; }

// Validation on, the loader quiet (a private 0700 XDG_RUNTIME_DIR), and whether the device is here.
bool device_ready(std::string* why) {
    static bool ready = [] {
        std::string runtime = prism::test::temp_dir("vulkan-xdg-runtime").string();
        chmod(runtime.c_str(), 0700);
        setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
        setenv("PRISM_VULKAN_VALIDATION", "1", 1);
        return true;
    }();
    (void)ready;
    std::string reason;
    if (!prism::test::backend_available("vulkan", &reason)) {
        *why = "no Vulkan device: " + reason;
        return false;
    }
    std::string filter = prism::parse_backend_spec(kDevice).device_filter;
    for (const prism::BackendFactory& f : prism::registered_backends())
        if (f.name == "vulkan")
            for (const std::string& d : f.probe().devices) {
                std::string lower_d = d, lower_f = filter;
                for (char& c : lower_d) c = char(std::tolower(static_cast<unsigned char>(c)));
                for (char& c : lower_f) c = char(std::tolower(static_cast<unsigned char>(c)));
                if (lower_d.find(lower_f) != std::string::npos) return true;
            }
    *why = "Vulkan is available but not " + kDevice +
           (on_lavapipe() ? " (apt-get install mesa-vulkan-drivers, or set PRISM_TEST_VULKAN_DEVICE)" : "");
    return false;
}

class Vulkan : public ::testing::Test {
protected:
    void SetUp() override {
        std::string why;
        if (!device_ready(&why)) GTEST_SKIP() << why;
        prism::vulkan_clear_debug_messages();
    }
    void TearDown() override {
        if (IsSkipped()) return;
        std::vector<std::string> messages = prism::vulkan_debug_messages();
        EXPECT_TRUE(messages.empty()) << messages.size() << " validation/driver message(s), the first: "
                                      << (messages.empty() ? "" : messages.front());
    }
};

std::string resolve(const std::string& spec) {
    return spec.rfind("builtin:", 0) == 0 ? spec : prism::test::scene(spec).string();
}

// The BVH layout is the one the renderer would pick for this backend: stack, or $PRISM_BVH_LAYOUT (so the whole
// suite can run on another layout); the tests that name a layout pass it.
prism::DeviceScene load(const std::string& spec, prism::Scene* out = nullptr,
                        prism::BvhLayout layout = prism::resolve_bvh_layout("auto", "vulkan")) {
    prism::LoadOptions options;
    options.data_dir = prism::test::scenes_dir();
    prism::Scene scene = prism::load_scene(resolve(spec), options);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    prism::DeviceScene device = prism::build_device_scene(scene, bvh);
    if (out) *out = std::move(scene);
    return device;
}

}  // namespace

// ---- The layout contract, GLSL std430 side ---------------------------------------------------------------------
// shaders/layout_check.comp writes into elements 0 and 1 of every device array a marker per 4-byte word:
// binding * 1000 + element * 500 + (the word index layout_table.h gives the member + component).
TEST_F(Vulkan, Std430LayoutMatchesTheLayoutTable) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    std::span<const uint32_t> spirv = prism::vulkan_embedded_spirv("layout_check");
    ASSERT_FALSE(spirv.empty());
    for (size_t a = 0; a < prism::device_array_count; ++a) {
        auto array = prism::DeviceArray(a);
        std::vector<uint8_t> fill(2 * prism::device_array_element_size(array), 0xff);
        backend->allocate(array, fill.size());
        backend->write(array, fill.data(), fill.size());
    }
    prism::vulkan_dispatch_module(*backend, spirv, 1);
    backend->finish();

    struct Member {
        const char* structure;
        const char* member;
        uint32_t offset;
        bool is_float;
    };
    std::vector<Member> members;
    std::map<std::string, uint32_t> sizes;
#define RT_LAYOUT_STRUCT(name, size) sizes[#name] = size;
#define RT_LAYOUT_MEMBER(name, member, offset, kind) members.push_back({#name, #member, offset, std::strcmp(#kind, "f4") == 0});
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER

    int structs_checked = 0, members_checked = 0;
#define RT_DATA_ARRAY(slot, type, name, access) {                                                                 \
        std::vector<uint8_t> bytes(2 * sizeof(type));                                                            \
        backend->read(prism::DeviceArray::name, bytes.data(), bytes.size());                                      \
        auto word = [&](uint32_t element, uint32_t byte_offset, bool as_float) {                                 \
            uint32_t u;                                                                                           \
            std::memcpy(&u, bytes.data() + element * sizeof(type) + byte_offset, 4);                              \
            float f;                                                                                              \
            std::memcpy(&f, &u, 4);                                                                               \
            return as_float ? double(f) : double(u);                                                              \
        };                                                                                                        \
        if (sizes.count(#type)) {                                                                                 \
            ++structs_checked;                                                                                    \
            EXPECT_EQ(sizes[#type], sizeof(type)) << #type;                                                       \
            for (const Member& m : members) {                                                                     \
                if (std::string(m.structure) != #type) continue;                                                  \
                ++members_checked;                                                                                \
                for (uint32_t e = 0; e < 2; ++e)                                                                  \
                    for (uint32_t c = 0; c < 4; ++c)                                                              \
                        EXPECT_EQ(word(e, m.offset + 4 * c, m.is_float), double(slot * 1000 + e * 500 + m.offset / 4 + c)) \
                            << #type "." << m.member << " element " << e << " component " << c                   \
                            << " (array '" #name "', binding " << slot << ")";                                  \
            }                                                                                                     \
        } else if (sizeof(type) == 4) {                                                                           \
            EXPECT_EQ(word(0, 0, false), double(slot * 1000)) << #name;                                           \
            EXPECT_EQ(word(1, 0, false), double(slot * 1000 + 500)) << #name " stride";                           \
        } else {                                                                                                  \
            for (uint32_t e = 0; e < 2; ++e)                                                                      \
                for (uint32_t c = 0; c < 4; ++c)                                                                  \
                    EXPECT_EQ(word(e, 4 * c, true), double(slot * 1000 + e * 500 + c)) << #name;                  \
        }                                                                                                         \
    }
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    EXPECT_EQ(structs_checked, int(sizes.size()));
    EXPECT_EQ(members_checked, int(members.size()));
}

// The checker checks: an invalid command (more work-groups than lavapipe's maxComputeWorkGroupCount of 65535)
// reaches the message log, so the empty log the other tests demand means something.
TEST_F(Vulkan, ValidationMessagesAreRecorded) {
    if (!on_lavapipe()) GTEST_SKIP() << "uses lavapipe's work-group limit";
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    for (size_t a = 0; a < prism::device_array_count; ++a)
        backend->allocate(prism::DeviceArray(a), 2 * prism::device_array_element_size(prism::DeviceArray(a)));
    prism::vulkan_dispatch_module(*backend, prism::vulkan_embedded_spirv("layout_check"), 65536);
    backend->finish();
    std::vector<std::string> messages = prism::vulkan_debug_messages();
    ASSERT_FALSE(messages.empty()) << "the validation layer is not active";
    EXPECT_NE(messages.front().find("groupCountX"), std::string::npos) << messages.front();
    prism::vulkan_clear_debug_messages();   // expected ones
}

// ---- Agreement with the cpu-ref oracle -------------------------------------------------------------------------
struct Case {
    std::string scene;
    uint32_t width, height, depth;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

class VulkanAgreement : public Vulkan, public ::testing::WithParamInterface<Case> {};

TEST_P(VulkanAgreement, ImageMatchesReference) {
    const Case& c = GetParam();
    prism::Scene scene;
    prism::DeviceScene device = load(c.scene, &scene);
    prism::RenderSettings settings;
    settings.width = c.width;
    settings.height = c.height;
    settings.max_depth = c.depth;
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
    prism::FrameResult actual = prism::RenderEngine(kDevice, device).render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    // Every depth traced what the oracle traced, up to rounding: GPU float math (FMA contraction, sqrt/division
    // precision) may tip a grazing ray or light the other way (dragon: 1 shadow ray in 9331), and a ray tipped at one
    // depth splits into reflection and refraction at the next (TransmissionTest on NVIDIA: 2 shadow rays of 1276 at
    // depth 3): a few rays of slack on small counts.
    auto near = [](const std::vector<uint32_t>& e, const std::vector<uint32_t>& a, const char* what) {
        ASSERT_EQ(e.size(), a.size()) << what;
        for (size_t d = 0; d < e.size(); ++d)
            EXPECT_LE(std::abs(double(e[d]) - double(a[d])), std::max(4.0, e[d] * 1e-3)) << what << " at depth " << d;
    };
    near(expected.stats.rays_per_depth, actual.stats.rays_per_depth, "rays");
    near(expected.stats.shadow_rays_per_depth, actual.stats.shadow_rays_per_depth, "shadow rays");
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10) << "the scene should be visible";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, VulkanAgreement,
    ::testing::Values(Case{"builtin:sphere", 96, 72, 4}, Case{"builtin:bunny", 96, 72, 4},
                      Case{"builtin:dragon", 96, 72, 4},
                      Case{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 96, 96, 4},
                      Case{"gltf/TransmissionTest/TransmissionTest.glb", 96, 72, 4},
                      Case{"gltf/BoxTextured/BoxTextured.glb", 64, 64, 4}),
    [](const ::testing::TestParamInfo<Case>& info) {
        std::string name = info.param.scene.substr(info.param.scene.find_last_of(":/") + 1);
        for (char& ch : name)
            if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
        return name;
    });

// Closest hits of random rays through the scene's bounds: same instance and primitive, same t.
static void expect_ray_queries_match_reference(const prism::DeviceScene& device) {
    prism::Aabb bounds = prism::node_bounds(device.top_level.nodes[0]);   // the world box, whatever the layout
    float lower[3] = {bounds.lower.x, bounds.lower.y, bounds.lower.z};
    float upper[3] = {bounds.upper.x, bounds.upper.y, bounds.upper.z};
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<prism::RayQuery> rays(4000);
    for (prism::RayQuery& q : rays) {
        float target[3], direction[3], length = 0.0f;
        for (int k = 0; k < 3; ++k) {
            float extent = upper[k] - lower[k];
            q.origin[k] = lower[k] - 0.5f * extent + 2.0f * extent * unit(random);   // around and inside
            target[k] = lower[k] + extent * unit(random);
            direction[k] = target[k] - q.origin[k];
            length += direction[k] * direction[k];
        }
        for (int k = 0; k < 3; ++k) q.direction[k] = direction[k] / std::sqrt(length);
        q.tmin = 0.0f;
        q.tmax = INFINITY;
    }
    std::vector<prism::RayHit> expected = prism::RenderEngine("cpu-ref", device).trace(rays, false);
    std::vector<prism::RayHit> actual = prism::RenderEngine(kDevice, device).trace(rays, false);
    ASSERT_EQ(expected.size(), actual.size());
    size_t agree = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const prism::RayHit &e = expected[i], &a = actual[i];
        bool e_hit = std::isfinite(e.t), a_hit = std::isfinite(a.t);
        hits += e_hit;
        if (e_hit != a_hit) continue;
        if (!e_hit || (e.instance == a.instance && e.primitive == a.primitive &&
                       std::fabs(e.t - a.t) <= 1e-4f * std::fabs(e.t)))
            ++agree;
    }
    EXPECT_GT(hits, rays.size() / 4) << "the rays should mostly hit the bunny";
    EXPECT_GE(double(agree), 0.9999 * double(rays.size())) << agree << " of " << rays.size() << " agree";
}

TEST_F(Vulkan, RayQueriesMatchReferenceHits) { expect_ray_queries_match_reference(load("builtin:bunny")); }

TEST_F(Vulkan, TwoRendersAreBitIdentical) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene);
    prism::RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    settings.max_depth = 5;
    prism::RenderEngine engine(kDevice, device);
    settings.read_radiance = true;
    prism::FrameResult a = engine.render(scene.camera, settings);
    prism::FrameResult b = engine.render(scene.camera, settings);
    EXPECT_EQ(a.image, b.image);
    ASSERT_FALSE(a.radiance.empty());
    EXPECT_EQ(a.radiance, b.radiance);
}

// Every enqueued stage comes back from finish() once, with its depth and a device time.
TEST_F(Vulkan, StageTimingsComeFromTimestamps) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene);
    prism::RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    settings.max_depth = 3;
    prism::FrameResult frame = prism::RenderEngine(kDevice, device).render(scene.camera, settings);
    ASSERT_EQ(frame.stats.stages.size(), 2u + 4u * 3u);   // generate, 4 stages per depth, resolve
    EXPECT_EQ(frame.stats.stages.front().stage, prism::Stage::Generate);
    EXPECT_EQ(frame.stats.stages.back().stage, prism::Stage::Resolve);
    EXPECT_EQ(frame.stats.stages[1 + 4 * 2].stage, prism::Stage::Intersect);
    EXPECT_EQ(frame.stats.stages[1 + 4 * 2].depth, 2u);
    double total = 0.0;
    for (const prism::StageTiming& t : frame.stats.stages) {
        EXPECT_GE(t.milliseconds, 0.0);
        EXPECT_LT(t.milliseconds, 1e6) << "a timestamp difference this large is a wrapped counter";
        total += t.milliseconds;
    }
    EXPECT_GT(total, 0.0);
}

// ---- Memory and errors ------------------------------------------------------------------------------------------
TEST_F(Vulkan, WritesReadsAndZeroesRoundTrip) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    // Larger than one staging/read-back piece (64 MiB), so the chunked paths run.
    std::vector<uint32_t> data((80u << 20) / 4);
    for (size_t i = 0; i < data.size(); ++i) data[i] = uint32_t(i * 2654435761u);
    backend->allocate(prism::DeviceArray::texels, data.size() * 4);
    backend->write(prism::DeviceArray::texels, data.data(), data.size() * 4);
    std::vector<uint32_t> back(data.size());
    backend->read(prism::DeviceArray::texels, back.data(), back.size() * 4);
    EXPECT_TRUE(back == data);
    uint32_t part[3] = {1, 2, 3};
    backend->write(prism::DeviceArray::texels, part, sizeof part, 40);
    uint32_t window[5];
    backend->read(prism::DeviceArray::texels, window, sizeof window, 36);
    EXPECT_EQ(window[0], data[9]);
    EXPECT_EQ(window[1], 1u);
    EXPECT_EQ(window[3], 3u);
    EXPECT_EQ(window[4], data[13]);
    backend->zero(prism::DeviceArray::texels);
    backend->read(prism::DeviceArray::texels, window, sizeof window, 36);
    for (uint32_t w : window) EXPECT_EQ(w, 0u);
    EXPECT_THROW(backend->read(prism::DeviceArray::texels, window, sizeof window, data.size() * 4 - 8), prism::Error);
}

// ---- Addressing and indirect launches ----------------------------------------------------------------------------
using prism::test::ScopedEnv;

prism::FrameResult render_with(const std::string& spec, const prism::DeviceScene& device, const prism::Camera& camera,
                               const prism::RenderSettings& settings, prism::VulkanLaunchMode* mode = nullptr) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(spec);
    prism::Renderer renderer(*backend, device);
    prism::FrameResult frame = renderer.render(camera, settings);
    if (mode) *mode = prism::vulkan_launch_mode(*backend);
    return frame;
}

// A ray queue larger than maxStorageBufferRange (lavapipe: 128 MiB) switches the stages to buffer device
// addresses by themselves, and the image still equals the oracle's.
TEST_F(Vulkan, QueueAboveMaxStorageBufferRangeRendersThroughAddresses) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", &scene);
    prism::RenderSettings settings;
    settings.width = 128;
    settings.height = 96;
    settings.max_depth = 3;
    settings.queue_factor = 96.0f;   // 1.2 M rays: 151 MiB of ray queue, the largest array
    prism::VulkanLaunchMode mode;
    prism::FrameResult actual = render_with(kDevice, device, scene.camera, settings, &mode);
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    size_t queue_bytes = size_t(actual.stats.queue_capacity) * 2 * sizeof(Ray);
    if (on_lavapipe()) {
        ASSERT_GT(queue_bytes, size_t(128) << 20) << "the queue must exceed lavapipe's maxStorageBufferRange";
        EXPECT_TRUE(mode.addresses);
    }
    EXPECT_TRUE(mode.indirect);
}

// Address mode traces every node layout the GPU kernels have, in scenes of one and of two instances (lavapipe once
// read the frame's layout field as its instance count there: two instances took the wide path, one the escape path).
TEST_F(Vulkan, AddressModeTracesEveryLayout) {
    if (!on_lavapipe()) GTEST_SKIP() << "checks lavapipe's buffer-address mode";
    ScopedEnv addresses("PRISM_VULKAN_ADDRESSING", "addresses");
    for (const char* spec : {"builtin:sphere", "stanford/bunny.ply"})
        for (prism::BvhLayout layout : {prism::BvhLayout::Stack, prism::BvhLayout::Escape}) {
            SCOPED_TRACE(std::string(spec) + ", " + prism::bvh_layout_name(layout));
            prism::Scene scene;
            prism::DeviceScene device = load(spec, &scene, layout);
            prism::RenderSettings settings;
            settings.width = 64;
            settings.height = 48;
            settings.max_depth = 3;
            prism::VulkanLaunchMode mode;
            prism::FrameResult actual = render_with(kDevice, device, scene.camera, settings, &mode);
            EXPECT_TRUE(mode.addresses);
            prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
            EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
            prism::test::expect_ray_counts_near(expected.stats, actual.stats);
        }
}

// Each way of launching gives the same bits: descriptors or addresses, indirect or fixed-grid dispatch.
TEST_F(Vulkan, AddressesAndFixedDispatchGiveIdenticalImages) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:bunny", &scene);
    prism::RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    settings.max_depth = 5;
    prism::VulkanLaunchMode mode;
    prism::FrameResult base = render_with(kDevice, device, scene.camera, settings, &mode);
    EXPECT_FALSE(mode.addresses);
    EXPECT_TRUE(mode.indirect);
    {
        ScopedEnv addresses("PRISM_VULKAN_ADDRESSING", "addresses");
        prism::FrameResult frame = render_with(kDevice, device, scene.camera, settings, &mode);
        EXPECT_TRUE(mode.addresses);
        EXPECT_EQ(base.image, frame.image);
        EXPECT_EQ(base.stats.rays_per_depth, frame.stats.rays_per_depth);
    }
    {
        ScopedEnv fixed("PRISM_VULKAN_DISPATCH", "fixed");
        prism::FrameResult frame = render_with(kDevice, device, scene.camera, settings, &mode);
        EXPECT_FALSE(mode.indirect);
        EXPECT_EQ(base.image, frame.image);
    }
}

TEST_F(Vulkan, UnknownLaunchSettingIsAnErrorNamingTheVariable) {
    ScopedEnv bad("PRISM_VULKAN_ADDRESSING", "pointers");
    try {
        prism::create_backend(kDevice);
        FAIL() << "an unknown PRISM_VULKAN_ADDRESSING should throw";
    } catch (const prism::Error& e) {
        EXPECT_NE(std::string(e.what()).find("PRISM_VULKAN_ADDRESSING=pointers"), std::string::npos) << e.what();
    }
}

// With descriptors forced, an array above maxStorageBufferRange is refused with the limit named.
TEST_F(Vulkan, DescriptorsOnlyRefuseArraysAboveMaxStorageBufferRange) {
    ScopedEnv descriptors("PRISM_VULKAN_ADDRESSING", "descriptors");
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    size_t limit = backend->info().max_buffer;
    try {
        backend->allocate(prism::DeviceArray::rays, limit + 16);
        FAIL() << "allocating past maxStorageBufferRange should throw";
    } catch (const prism::Error& e) {
        std::string message = e.what();
        EXPECT_NE(message.find("'rays'"), std::string::npos) << message;
        if (on_lavapipe()) {
            EXPECT_NE(message.find("maxStorageBufferRange"), std::string::npos) << message;
        }
    }
}

TEST_F(Vulkan, BufferAboveTheLargestAllocationNamesBufferAndLimit) {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    size_t limit = backend->info().max_buffer;
    ASSERT_GT(limit, 0u);
    try {
        backend->allocate(prism::DeviceArray::rays, limit + 16);
        FAIL() << "allocating past the limit should throw";
    } catch (const prism::Error& e) {
        std::string message = e.what();
        EXPECT_NE(message.find("'rays'"), std::string::npos) << message;
        EXPECT_NE(message.find(backend->info().device), std::string::npos) << message;
        EXPECT_NE(message.find("MiB"), std::string::npos) << message;
    }
}

TEST_F(Vulkan, UnknownDeviceIsAnErrorListingTheDevices) {
    try {
        prism::create_backend("vulkan:no-such-gpu");
        FAIL() << "an unknown device should throw";
    } catch (const prism::Error& e) {
        std::string message = e.what();
        EXPECT_NE(message.find("no-such-gpu"), std::string::npos) << message;
        EXPECT_NE(message.find(prism::create_backend(kDevice)->info().device), std::string::npos) << message;
    }
}

TEST_F(Vulkan, ProbeListsDevicesWithDriverNames) {
    for (const prism::BackendFactory& f : prism::registered_backends()) {
        if (f.name != "vulkan") continue;
        prism::BackendAvailability a = f.probe();
        EXPECT_TRUE(a.available) << a.detail;
        bool found = false;
        for (const std::string& d : a.devices) found |= d.find(", Vulkan 1.") != std::string::npos;
        EXPECT_TRUE(found) << "devices should read 'name [driver, Vulkan x.y.z]'";
        if (on_lavapipe()) {
            found = false;
            for (const std::string& d : a.devices) found |= d.find("[llvmpipe, Vulkan 1.") != std::string::npos;
            EXPECT_TRUE(found) << "lavapipe's driver name is llvmpipe";
        }
    }
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    EXPECT_EQ(backend->info().name, "vulkan");
    EXPECT_FALSE(backend->info().device.empty());
    EXPECT_NE(backend->info().driver.find("grid"), std::string::npos);
}

#endif  // PRISM_HAVE_VULKAN
