// What is particular to the vulkan backend, on Mesa lavapipe (vulkan:llvmpipe; $PRISM_TEST_VULKAN_DEVICE picks
// another, e.g. vulkan:nvidia on the GPU machine), always with VK_LAYER_KHRONOS_validation: any warning or error a
// layer or the driver reports fails the test. The GLSL side of the layout contract, validation messages, buffer
// device addresses and indirect dispatch, and Vulkan's limits; the contract every backend keeps is in
// test_backend_contract.cpp. Skipped, with the reason, where no Vulkan device (or not the chosen one) is present.
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
#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace {

// The device under test: $PRISM_TEST_VULKAN_DEVICE (e.g. "vulkan:nvidia" on the GPU machine), else lavapipe.
std::string device_spec() { return prism::test::test_device("vulkan"); }
const std::string kDevice = device_spec();
bool on_lavapipe() { return kDevice.find("llvmpipe") != std::string::npos; }

// Whether the device is here (and, once asked, validation on: prism::test::begin_backend_checks).
bool device_ready(std::string* why) {
    prism::test::begin_backend_checks(kDevice);
    if (prism::test::backend_spec_runs_here(kDevice, why)) return true;
    *why = "no " + kDevice + ": " + *why +
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

// The BVH layout is the one the renderer would pick for this backend: stack, or $PRISM_BVH_LAYOUT (so the whole
// suite can run on another layout); the tests that name a layout pass it.
prism::DeviceScene load(const std::string& spec, prism::Scene* out = nullptr,
                        prism::BvhLayout layout = prism::resolve_bvh_layout("auto", "vulkan")) {
    return prism::test::load_device_scene(spec, out, layout);
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
        uint32_t words;  // 4 for a float4/uint4, 1 for a scalar
    };
    std::vector<Member> members;
    std::map<std::string, uint32_t> sizes;
#define RT_LAYOUT_STRUCT(name, size) sizes[#name] = size;
#define RT_LAYOUT_MEMBER(name, member, offset, kind) \
    members.push_back({#name, #member, offset, #kind[0] == 'f', #kind[1] == '4' ? 4u : 1u});
#include "kernels/layout_table.h"
#undef RT_LAYOUT_STRUCT
#undef RT_LAYOUT_MEMBER

    int structs_checked = 0, members_checked = 0;
#define RT_DATA_ARRAY(slot, type, name, access, role)                                            \
    {                                                                                            \
        std::vector<uint8_t> bytes(2 * sizeof(type));                                            \
        backend->read(prism::DeviceArray::name, bytes.data(), bytes.size());                     \
        auto word = [&](uint32_t element, uint32_t byte_offset, bool as_float) {                 \
            uint32_t u;                                                                          \
            std::memcpy(&u, bytes.data() + element * sizeof(type) + byte_offset, 4);             \
            float f;                                                                             \
            std::memcpy(&f, &u, 4);                                                              \
            return as_float ? double(f) : double(u);                                             \
        };                                                                                       \
        if (sizes.count(#type)) {                                                                \
            ++structs_checked;                                                                   \
            EXPECT_EQ(sizes[#type], sizeof(type)) << #type;                                      \
            for (const Member& m : members) {                                                    \
                if (std::string(m.structure) != #type) continue;                                 \
                ++members_checked;                                                               \
                for (uint32_t e = 0; e < 2; ++e)                                                 \
                    for (uint32_t c = 0; c < m.words; ++c)                                       \
                        EXPECT_EQ(word(e, m.offset + 4 * c, m.is_float),                         \
                                  double(slot * 1000 + e * 500 + m.offset / 4 + c))              \
                            << #type "." << m.member << " element " << e << " component " << c   \
                            << " (array '" #name "', binding " << slot << ")";                   \
            }                                                                                    \
        } else if (sizeof(type) == 4) {                                                          \
            EXPECT_EQ(word(0, 0, false), double(slot * 1000)) << #name;                          \
            EXPECT_EQ(word(1, 0, false), double(slot * 1000 + 500)) << #name " stride";          \
        } else {                                                                                 \
            for (uint32_t e = 0; e < 2; ++e)                                                     \
                for (uint32_t c = 0; c < 4; ++c)                                                 \
                    EXPECT_EQ(word(e, 4 * c, true), double(slot * 1000 + e * 500 + c)) << #name; \
        }                                                                                        \
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
    prism::vulkan_clear_debug_messages();  // expected ones
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
    prism::RenderSettings settings = prism::test::small_settings(128, 96, 3);
    settings.queue_factor = 96.0f;  // 1.2 M rays: 151 MiB of ray queue, the largest array
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
            prism::RenderSettings settings = prism::test::small_settings(64, 48, 3);
            prism::VulkanLaunchMode mode;
            prism::FrameResult actual = render_with(kDevice, device, scene.camera, settings, &mode);
            EXPECT_TRUE(mode.addresses);
            prism::FrameResult expected = prism::RenderEngine("cpu-ref", device).render(scene.camera, settings);
            EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
            prism::test::expect_ray_counts_near(expected.stats, actual.stats);
        }
}

// Each way of launching and waiting gives the same bits: descriptors or addresses, indirect or fixed-grid
// dispatch, the host polling the frame's fence (on a GPU; on a CPU device, whose stages need every core, it sleeps
// in vkWaitForFences) or sleeping (PRISM_VULKAN_WAIT=block).
TEST_F(Vulkan, EveryWayOfLaunchingAndWaitingGivesIdenticalImages) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:bunny", &scene);
    prism::RenderSettings settings = prism::test::small_settings(80, 60, 5);
    prism::VulkanLaunchMode mode;
    prism::FrameResult base = render_with(kDevice, device, scene.camera, settings, &mode);
    EXPECT_FALSE(mode.addresses);
    EXPECT_TRUE(mode.indirect);
    EXPECT_EQ(mode.polls_fence, !on_lavapipe());  // the tests run on lavapipe or on a GPU
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
    {
        ScopedEnv block("PRISM_VULKAN_WAIT", "block");
        prism::FrameResult frame = render_with(kDevice, device, scene.camera, settings, &mode);
        EXPECT_FALSE(mode.polls_fence);
        EXPECT_EQ(base.image, frame.image);
        EXPECT_EQ(base.stats.stages.size(), frame.stats.stages.size());
    }
}

TEST_F(Vulkan, UnknownLaunchSettingIsAnErrorNamingTheVariable) {
    ScopedEnv bad("PRISM_VULKAN_ADDRESSING", "pointers");
    try {
        prism::create_backend(kDevice);
        FAIL() << "an unknown PRISM_VULKAN_ADDRESSING should throw";
    } catch (const prism::Error& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "vulkan: PRISM_VULKAN_ADDRESSING='pointers' is not one of auto, descriptors, addresses"),
                  std::string::npos)
            << e.what();
    }
}

// What allocating the rays array 16 bytes past the backend's largest buffer throws (it must throw, naming the array).
static std::string refusal_past_the_largest_buffer() {
    std::unique_ptr<prism::Backend> backend = prism::create_backend(kDevice);
    size_t limit = backend->info().max_buffer;
    EXPECT_GT(limit, 0u);
    std::string message = prism::test::error_message([&] { backend->allocate(prism::DeviceArray::rays, limit + 16); });
    EXPECT_NE(message.find("'rays'"), std::string::npos) << message;
    return message;
}

// With descriptors forced, an array above maxStorageBufferRange is refused with the limit named.
TEST_F(Vulkan, DescriptorsOnlyRefuseArraysAboveMaxStorageBufferRange) {
    ScopedEnv descriptors("PRISM_VULKAN_ADDRESSING", "descriptors");
    std::string message = refusal_past_the_largest_buffer();
    if (on_lavapipe()) {
        EXPECT_NE(message.find("maxStorageBufferRange"), std::string::npos) << message;
    }
}

TEST_F(Vulkan, BufferAboveTheLargestAllocationNamesBufferAndLimit) {
    std::string message = refusal_past_the_largest_buffer();
    EXPECT_NE(message.find(prism::create_backend(kDevice)->info().device), std::string::npos) << message;
    EXPECT_NE(message.find("MiB"), std::string::npos) << message;
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
