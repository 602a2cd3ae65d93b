// BVH builds report their progress (the fraction of primitives placed in leaves) for the command line's ETA: it
// rises, ends at exactly 1, and spans every mesh of a scene.
#include <algorithm>
#include <mutex>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/bvh/bvh.h"
#include "core/render/device_scene.h"
#include "core/loaders/scene_loader.h"

namespace prism {
namespace {

std::vector<Aabb> random_boxes(size_t count, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> position(-10.0f, 10.0f), size(0.01f, 0.5f);
    std::vector<Aabb> boxes(count);
    for (Aabb& box : boxes) {
        glm::vec3 lower(position(random), position(random), position(random));
        box.grow(lower);
        box.grow(lower + glm::vec3(size(random), size(random), size(random)));
    }
    return boxes;
}

// Collects what a build reports (from any of its threads).
struct Reports {
    std::mutex mutex;
    std::vector<double> fractions;
    BvhProgress callback() {
        return [this](double fraction) {
            std::lock_guard lock(mutex);
            fractions.push_back(fraction);
        };
    }
};

TEST(BvhProgress, RisesToOneAtMostOncePerPercent) {
    for (BvhLayout layout : {BvhLayout::Stack, BvhLayout::Wide}) {
        for (uint32_t threads : {1u, 4u}) {
            Reports reports;
            BvhBuildOptions options;
            options.layout = layout;
            options.threads = threads;
            build_bvh(random_boxes(20000, 3), options, reports.callback());
            ASSERT_FALSE(reports.fractions.empty());
            EXPECT_LE(reports.fractions.size(), 100u);
            // Whichever thread places the last primitive reports exactly 1.
            EXPECT_EQ(*std::max_element(reports.fractions.begin(), reports.fractions.end()), 1.0);
            for (double fraction : reports.fractions) {
                EXPECT_GT(fraction, 0.0);
                EXPECT_LE(fraction, 1.0);
            }
        }
    }
}

TEST(BvhProgress, SpansEveryMeshOfAScene) {
    Scene scene = load_scene("builtin:sphere", LoadOptions{});
    ASSERT_GT(scene.meshes.size(), 1u);
    Reports reports;
    BvhBuildOptions options;
    options.threads = 1;  // one thread: the reports arrive in order
    build_device_scene(scene, options, reports.callback());
    ASSERT_GE(reports.fractions.size(), 2u);
    EXPECT_TRUE(std::is_sorted(reports.fractions.begin(), reports.fractions.end()));
    EXPECT_DOUBLE_EQ(reports.fractions.back(), 1.0);
    EXPECT_LT(reports.fractions.front(), 0.9) << "the first mesh reports its share, not the whole";
}

}  // namespace
}  // namespace prism
