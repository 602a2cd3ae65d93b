// The hit-level oracle (issue: "prism rays on the cpu backend agrees with Embree on rays it has never seen"):
// 1M rays per model — primary rays from the default camera plus cosine-distributed diffuse rays from their hits,
// freshly seeded — go through the `prism rays` command and through Embree; at least 99.99% must report the same
// primitive (or both miss), with t within 1e-4 relative.
#ifdef PRISM_HAVE_EMBREE

#include <cstring>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "bench/embree_oracle.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace {

// The cpu backend is checked through the `prism rays` command (the user's path); GPU backends through the same
// RenderEngine::trace in this process, because a child process cannot open a GPU that this test process already
// holds when the GPU is in exclusive-process compute mode (as on the H100 machine).
// `layout`: the --bvh-layout the cpu backend's `prism rays` gets (auto: wide), or the layout a GPU backend's scene
// is built with (auto: what the renderer picks for it).
void check_against_embree(const std::string& model, const std::string& backend, size_t total,
                          const std::string& layout = "auto") {
    std::string path = prism::test::scene(model).string();
    prism::Scene scene = prism::load_scene(path);
    prism::oracle::EmbreeScene embree(scene);
    prism::oracle::OracleRays rays = prism::oracle::make_oracle_rays(scene, embree, total / 2, total, 20261124);
    ASSERT_EQ(rays.rays.size(), total);
    ASSERT_GT(rays.diffuse, total / 3) << "the camera should see the model";

    std::vector<prism::RayHit> prism_hits(total);
    if (backend == "cpu") {
        // One pair of files per test: ctest runs these tests side by side in separate processes.
        std::string tag = std::filesystem::path(model).stem().string() + "-" + layout;
        std::filesystem::path dir = prism::test::temp_dir("embree-oracle");
        std::filesystem::path in = dir / (tag + "-rays.bin"), out = dir / (tag + "-hits.bin");
        std::ofstream(in, std::ios::binary)
            .write(reinterpret_cast<const char*>(rays.rays.data()),
                   std::streamsize(rays.rays.size() * sizeof(prism::RayQuery)));
        prism::test::CommandResult run =
            prism::test::run_prism("rays --scene '" + path + "' --backend " + backend + " --bvh-layout " + layout +
                                   " --rays '" + in.string() + "' --out '" + out.string() + "'");
        ASSERT_EQ(run.exit_code, 0) << run.output;
        std::ifstream file(out, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
        ASSERT_EQ(bytes.size(), total * 20);
        std::memcpy(prism_hits.data(), bytes.data(), bytes.size());
    } else {
        prism::BvhBuildOptions bvh;
        bvh.layout = prism::resolve_bvh_layout(layout, backend);
        prism::DeviceScene device = prism::build_device_scene(scene, bvh);
        prism_hits = prism::RenderEngine(backend, device).trace(rays.rays, false);
    }

    std::vector<prism::RayHit> embree_hits = embree.intersect1(rays.rays);
    prism::oracle::Agreement agreement = prism::oracle::compare_hits(prism_hits, embree_hits);
    EXPECT_GE(agreement.fraction(), 0.9999) << agreement.same << " of " << agreement.rays << " agree";
    EXPECT_LE(agreement.t_outside_tolerance, total / 10000) << "hits on the same triangle with t off by > 1e-4";
    size_t hits = 0;
    for (const prism::RayHit& h : prism_hits) hits += h.t < INFINITY;
    EXPECT_GT(hits, total / 10);  // most primary rays hit the model; most diffuse rays leave it
}

}  // namespace

// The cpu backend's default (wide) layout, and the stack layout the GPU backends default to.
TEST(EmbreeOracle, CpuBackendAgreesOnBunny) { check_against_embree("stanford/bunny.ply", "cpu", 1000000); }
TEST(EmbreeOracle, CpuBackendAgreesOnDragon) { check_against_embree("stanford/dragon.ply.gz", "cpu", 1000000); }
TEST(EmbreeOracle, CpuBackendStackLayoutAgreesOnBunny) {
    check_against_embree("stanford/bunny.ply", "cpu", 1000000, "stack");
}

// The GPU backends through RenderEngine::trace, on the tree the renderer builds for them: CUDA on the dragon,
// OpenCL and Vulkan (which CI runs on PoCL and lavapipe) on the bunny.
class EmbreeOracleOnGpu : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(EmbreeOracleOnGpu, AgreesOnTheModel) {
    const auto& [backend, model] = GetParam();
    std::string reason;
    if (!prism::test::backend_spec_runs_here(backend, &reason)) GTEST_SKIP() << reason;
    check_against_embree(model, backend, 1000000);
}

INSTANTIATE_TEST_SUITE_P(
    Backends, EmbreeOracleOnGpu,
    ::testing::Values(std::pair<std::string, std::string>{"cuda", "stanford/dragon.ply.gz"},
                      std::pair<std::string, std::string>{prism::test::test_device("opencl"), "stanford/bunny.ply"},
                      std::pair<std::string, std::string>{prism::test::test_device("vulkan"), "stanford/bunny.ply"}),
    [](const auto& info) { return prism::test::test_name_of(info.param.first); });

#endif  // PRISM_HAVE_EMBREE
