// How a frame comes back to the host (Renderer::render): through Backend::read_pinned, and, where page-locked
// memory runs out, through read() into the result itself, with the same image and radiance either way.
#include <gtest/gtest.h>

#include "core/render/render_engine.h"
#include "core/render/renderer.h"
#include "core/util/error.h"
#include "tests/test_support.h"

namespace {

// The cpu backend, except that read_pinned fails as a page-locked allocation can.
class NoPinnedMemory final : public prism::Backend {
public:
    explicit NoPinnedMemory(std::unique_ptr<prism::Backend> inner) : inner_(std::move(inner)) {}
    prism::BackendInfo info() const override { return inner_->info(); }
    void allocate(prism::DeviceArray array, size_t bytes) override { inner_->allocate(array, bytes); }
    void write(prism::DeviceArray array, const void* data, size_t bytes, size_t offset) override {
        inner_->write(array, data, bytes, offset);
    }
    void read(prism::DeviceArray array, void* data, size_t bytes, size_t offset) override {
        reads_ += 1;
        inner_->read(array, data, bytes, offset);
    }
    const void* read_pinned(prism::DeviceArray, size_t bytes) override {
        throw prism::Error("test: no page-locked memory for " + std::to_string(bytes) + " bytes");
    }
    void zero(prism::DeviceArray array) override { inner_->zero(array); }
    void enqueue(prism::Stage stage, uint32_t depth) override { inner_->enqueue(stage, depth); }
    std::vector<prism::StageTiming> finish() override { return inner_->finish(); }
    int reads() const { return reads_; }

private:
    std::unique_ptr<prism::Backend> inner_;
    int reads_ = 0;
};

TEST(RendererReadBack, WithoutPinnedMemoryTheFrameIsReadIntoTheResult) {
    prism::Scene scene;
    prism::DeviceScene device = prism::test::load_device_scene("builtin:sphere", &scene, prism::BvhLayout::Wide);
    prism::RenderSettings settings = prism::test::small_settings(64, 48, 3);
    settings.read_radiance = true;

    std::unique_ptr<prism::Backend> cpu = prism::create_backend("cpu");
    prism::FrameResult expected = prism::Renderer(*cpu, device).render(scene.camera, settings);

    NoPinnedMemory failing(prism::create_backend("cpu"));
    prism::FrameResult actual = prism::Renderer(failing, device).render(scene.camera, settings);
    EXPECT_GE(failing.reads(), 3);  // the counters, then the image and the radiance after read_pinned failed
    ASSERT_EQ(actual.image.size(), size_t(64) * 48);
    ASSERT_EQ(actual.radiance.size(), size_t(64) * 48 * 4);
    EXPECT_EQ(actual.image, expected.image);
    EXPECT_EQ(actual.radiance, expected.radiance);
}

}  // namespace
