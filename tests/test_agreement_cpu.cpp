// The `cpu` wavefront backend against the `cpu-ref` recursive oracle: same kernels/ functions, different
// scheduling (device-style queues, atomic appends, weights carried by rays). Accumulation is exact fixed point, so
// the images are expected to be identical; the requirement is PSNR >= 50 dB.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace {

struct Case {
    std::string scene;
    uint32_t width, height, depth;
    prism::BvhLayout layout = prism::BvhLayout::Stack;
    bool flatten = false;  // the wide layout: BvhBuildOptions::flatten_instances
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.scene; }

class CpuAgreement : public ::testing::TestWithParam<Case> {};

prism::DeviceScene load(const std::string& spec, prism::BvhLayout layout = prism::BvhLayout::Stack,
                        prism::BvhMethod method = prism::BvhMethod::BinnedSah, prism::Scene* out = nullptr,
                        bool flatten = false) {
    prism::Scene scene = prism::test::load_test_scene(spec);
    prism::BvhBuildOptions bvh;
    bvh.layout = layout;
    bvh.method = method;
    bvh.flatten_instances = flatten;
    prism::DeviceScene device = prism::build_device_scene(scene, bvh);
    if (out) *out = std::move(scene);
    return device;
}

}  // namespace

TEST_P(CpuAgreement, WavefrontMatchesRecursiveReference) {
    const Case& c = GetParam();
    prism::Scene scene;
    prism::DeviceScene device = load(c.scene, c.layout, prism::BvhMethod::BinnedSah, &scene, c.flatten);
    prism::RenderSettings settings = prism::test::small_settings(c.width, c.height, c.depth);
    prism::RenderEngine reference("cpu-ref", device);
    prism::RenderEngine wavefront("cpu", device);
    prism::FrameResult expected = reference.render(scene.camera, settings);
    prism::FrameResult actual = wavefront.render(scene.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
    EXPECT_EQ(expected.stats.rays_per_depth, actual.stats.rays_per_depth);
    EXPECT_EQ(expected.stats.shadow_rays_per_depth, actual.stats.shadow_rays_per_depth);
    // Not a black or flat image: the scene is actually visible.
    uint32_t distinct = 0;
    for (size_t i = 1; i < actual.image.size(); ++i) distinct += actual.image[i] != actual.image[0];
    EXPECT_GT(distinct, actual.image.size() / 10);
}

const Case kCases[] = {Case{"builtin:sphere", 160, 120, 8},
                       Case{"builtin:bunny", 160, 120, 6},
                       Case{"builtin:dragon", 128, 96, 6},
                       Case{"gltf/GlassVaseFlowers/GlassVaseFlowers.glb", 128, 128, 6},
                       Case{"gltf/TransmissionTest/TransmissionTest.glb", 128, 96, 6},
                       Case{"gltf/BoxTextured/BoxTextured.glb", 96, 96, 4},
                       Case{"gltf/OrientationTest/OrientationTest.glb", 128, 96, 4},
                       Case{"gltf/DamagedHelmet/DamagedHelmet.glb", 96, 96, 4},
                       Case{"gltf/IridescenceSuzanne/IridescenceSuzanne.glb", 128, 48, 5},
                       Case{"examples/spot-lights.json", 128, 96, 5},
                       Case{"gltf/MetalRoughSpheresNoTextures/MetalRoughSpheresNoTextures.glb", 128, 96, 4}};

std::vector<Case> with_layout(prism::BvhLayout layout, bool flatten = false) {
    std::vector<Case> cases(std::begin(kCases), std::end(kCases));
    for (Case& c : cases) c.layout = layout, c.flatten = flatten;
    return cases;
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string name = info.param.scene.substr(info.param.scene.find_last_of(":/") + 1);
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Scenes, CpuAgreement, ::testing::ValuesIn(with_layout(prism::BvhLayout::Stack)), case_name);
// The wide layout (the cpu backends' default): the cpu backend runs it from its AVX2 stages where the CPU has
// them, cpu-ref from the baseline build, so this also checks that both instruction sets trace the same hits.
INSTANTIATE_TEST_SUITE_P(WideScenes, CpuAgreement, ::testing::ValuesIn(with_layout(prism::BvhLayout::Wide)), case_name);
// The wide layout with flattened instances (what `prism render`, `rays` and `bench` build for the cpu backends).
INSTANTIATE_TEST_SUITE_P(FlatWideScenes, CpuAgreement, ::testing::ValuesIn(with_layout(prism::BvhLayout::Wide, true)),
                         case_name);

// Every node layout and both builders trace the same closest hits, so they render the same image.
TEST(CpuAgreement, LayoutsAndBuildersRenderTheSameImage) {
    prism::Scene scene;
    prism::DeviceScene stack = load("builtin:sphere", prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::DeviceScene escape = load("builtin:sphere", prism::BvhLayout::Escape, prism::BvhMethod::Median);
    prism::DeviceScene wide = load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah);
    prism::DeviceScene wide_median = load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::Median);
    prism::DeviceScene flat =
        load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, nullptr, true);
    prism::RenderSettings settings = prism::test::small_settings(96, 72);
    prism::FrameResult a = prism::RenderEngine("cpu", stack).render(scene.camera, settings);
    for (const prism::DeviceScene* other : {&escape, &wide, &wide_median, &flat}) {
        prism::FrameResult b = prism::RenderEngine("cpu", *other).render(scene.camera, settings);
        EXPECT_GE(prism::test::psnr_rgba8(a.image, b.image), 50.0)
            << prism::bvh_layout_name(other->bvh_options.layout) << (other == &flat ? " (flat)" : "");
        EXPECT_EQ(a.stats.rays_per_depth, b.stats.rays_per_depth);
    }
}

// The cpu backend's two builds of the stages (baseline SSE2 and AVX2, PRISM_CPU_ISA) give the same bits.
TEST(CpuAgreement, BaselineAndAvx2StagesAgreeBitForBit) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:bunny", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, &scene);
    prism::RenderSettings settings = prism::test::small_settings(96, 72, 6);
    auto render_with = [&](const char* isa) {
        prism::test::ScopedEnv env("PRISM_CPU_ISA", isa);
        return prism::RenderEngine("cpu", device).render(scene.camera, settings);
    };
    prism::FrameResult baseline = render_with("baseline");
    std::string reason;
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2";
    prism::FrameResult avx2 = render_with("avx2");
    EXPECT_EQ(baseline.image, avx2.image);
    EXPECT_EQ(baseline.radiance, avx2.radiance);
    EXPECT_EQ(baseline.stats.rays_per_depth, avx2.stats.rays_per_depth);
    EXPECT_EQ(baseline.stats.shadow_rays_per_depth, avx2.stats.shadow_rays_per_depth);
}

// Moving instances in the wide layout refits (or rebuilds) its top level in place: the frame equals one from a
// scene built with the instances already moved.
TEST(CpuAgreement, WideTopLevelRefitAndRebuildMatchAFreshBuild) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, &scene);
    ASSERT_GT(scene.instances.size(), 1u);
    std::vector<glm::mat4> transforms;
    for (size_t i = 0; i < scene.instances.size(); ++i)
        transforms.push_back(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f * float(i), 0.2f, -0.1f)) *
                             scene.instances[i].transform);
    prism::Scene moved = scene;
    for (size_t i = 0; i < moved.instances.size(); ++i) moved.instances[i].transform = transforms[i];
    prism::BvhBuildOptions wide;
    wide.layout = prism::BvhLayout::Wide;
    prism::DeviceScene fresh = prism::build_device_scene(moved, wide);
    prism::RenderSettings settings = prism::test::small_settings(96, 72);
    prism::FrameResult expected = prism::RenderEngine("cpu-ref", fresh).render(moved.camera, settings);
    for (bool rebuild : {false, true}) {
        SCOPED_TRACE(rebuild ? "rebuild" : "refit");
        prism::DeviceScene updated = device;
        prism::RenderEngine engine("cpu", updated);
        engine.update_instances(updated, transforms, rebuild);
        prism::FrameResult actual = engine.render(moved.camera, settings);
        EXPECT_GE(prism::test::psnr_rgba8(expected.image, actual.image), 50.0);
        EXPECT_EQ(expected.stats.rays_per_depth, actual.stats.rays_per_depth);
        EXPECT_EQ(prism::RenderEngine("cpu-ref", updated).render(moved.camera, settings).image, actual.image);
    }
}

// Flattened instances trace one world-space BVH, so they cannot move: an update says so instead of tracing a
// stale tree. The two-level wide layout (as `prism view` builds it) is what moving scenes use.
TEST(CpuAgreement, FlattenedInstancesRefuseToMove) {
    prism::Scene scene;
    prism::DeviceScene device =
        load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, &scene, true);
    std::vector<glm::mat4> transforms;
    for (const prism::Instance& instance : scene.instances) transforms.push_back(instance.transform);
    prism::RenderEngine engine("cpu", device);
    EXPECT_THROW(engine.update_instances(device, transforms, false), prism::Error);
}

// Flattening stores a mesh once per instance: a scene that instances a mesh heavily keeps the two-level layout
// (BvhBuildOptions::flatten_growth_limit), and says so in the built scene's options, and still renders the same.
TEST(CpuAgreement, InstancingHeavyScenesAreNotFlattened) {
    prism::Scene scene;
    prism::DeviceScene flat = load("builtin:sphere", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, &scene, true);
    EXPECT_TRUE(flat.bvh_options.flatten_instances);  // floor + one sphere: nothing repeats
    prism::Scene many = scene;
    const prism::Instance sphere = many.instances.back();
    for (int i = 1; i <= 2; ++i) {
        prism::Instance copy = sphere;
        copy.transform = glm::translate(glm::mat4(1.0f), glm::vec3(2.5f * float(i), 0.0f, -2.0f)) * sphere.transform;
        many.instances.push_back(copy);
    }
    prism::BvhBuildOptions bvh;
    bvh.layout = prism::BvhLayout::Wide;
    bvh.flatten_instances = true;
    prism::DeviceScene kept = prism::build_device_scene(many, bvh);
    EXPECT_FALSE(kept.bvh_options.flatten_instances);  // three spheres: three times the triangles
    bvh.flatten_growth_limit = 4.0f;
    prism::DeviceScene forced = prism::build_device_scene(many, bvh);
    EXPECT_TRUE(forced.bvh_options.flatten_instances);
    prism::RenderSettings settings = prism::test::small_settings(96, 72);
    prism::FrameResult a = prism::RenderEngine("cpu", kept).render(many.camera, settings);
    prism::FrameResult b = prism::RenderEngine("cpu", forced).render(many.camera, settings);
    EXPECT_GE(prism::test::psnr_rgba8(a.image, b.image), 50.0);
}

// Flattened and two-level wide layouts report the same hits (instance, primitive, triangle slot) for rays that
// cross several instances, with t, u, v as close as world- and object-space arithmetic allow.
TEST(CpuAgreement, FlattenedInstancesReportTheTwoLevelHits) {
    prism::Scene scene;
    prism::DeviceScene two_level = load("builtin:bunny", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, &scene);
    prism::DeviceScene flat = load("builtin:bunny", prism::BvhLayout::Wide, prism::BvhMethod::BinnedSah, nullptr, true);
    ASSERT_GT(scene.instances.size(), 2u);
    // A fan of rays from above the floor towards the model, the floor and the sky.
    std::vector<prism::RayQuery> rays;
    const glm::vec3 eye = scene.camera.position;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            glm::vec3 d = glm::normalize(scene.camera.target - eye +
                                         glm::vec3(0.05f * float(x - 32), 0.05f * float(y - 40), 0.0f));
            rays.push_back(prism::RayQuery{{eye.x, eye.y, eye.z}, 0.0f, {d.x, d.y, d.z}, INFINITY});
        }
    std::vector<prism::RayHit> a = prism::RenderEngine("cpu", two_level).trace(rays, false);
    std::vector<prism::RayHit> b = prism::RenderEngine("cpu", flat).trace(rays, false);
    std::set<uint32_t> instances_hit;
    size_t same = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        bool a_hit = a[i].t < INFINITY, b_hit = b[i].t < INFINITY;
        if (a_hit) instances_hit.insert(a[i].instance);
        if (a_hit != b_hit) continue;
        if (!a_hit || (a[i].instance == b[i].instance && a[i].primitive == b[i].primitive)) ++same;
        if (a_hit && a[i].instance == b[i].instance && a[i].primitive == b[i].primitive) {
            EXPECT_NEAR(a[i].t, b[i].t, 1e-4f * a[i].t) << "ray " << i;
        }
    }
    EXPECT_GE(instances_hit.size(), 2u) << "the rays should see more than one instance";
    EXPECT_GE(double(same), 0.999 * double(rays.size()));
}

// The viewer's in-frame copy into GL's buffer needs a backend with GL interop: asking the cpu backend (created
// without a GL context) fails in one message naming why, instead of silently showing nothing.
TEST(CpuAgreement, CopyToGlWithoutInteropIsAnError) {
    prism::Scene scene;
    prism::DeviceScene device = load("builtin:sphere", prism::BvhLayout::Stack, prism::BvhMethod::BinnedSah, &scene);
    prism::RenderSettings settings = prism::test::small_settings(32, 24);
    settings.copy_to_gl = true;
    prism::RenderEngine engine("cpu", device);
    std::string message = prism::test::error_message([&] { engine.render(scene.camera, settings); });
    EXPECT_EQ(message.rfind("render: copy_to_gl without a GL interop (", 0), 0u) << message;
}
