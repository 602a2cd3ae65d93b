// Renders small generated glTF scenes on cpu-ref and reads pixels back, for tests that check what a material
// channel does to the image (pixel probes), not only what the loader stored.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/image/image_io.h"
#include "core/loaders/load_gltf.h"
#include "core/render/render_engine.h"
#include "tests/test_support.h"

namespace prism::test {

struct Rgb {
    int r, g, b;
};

struct ProbeImage {
    FrameResult frame;
    Rgb at(uint32_t x, uint32_t y) const {
        uint32_t p = frame.image.at(y * frame.width + x);
        return {int(p & 255u), int((p >> 8) & 255u), int((p >> 16) & 255u)};
    }
    // The pixel at (sx, sy) in [-1, 1]^2 of the frame (x right, y up).
    Rgb at_ndc(float sx, float sy) const {
        auto x = static_cast<uint32_t>((sx * 0.5f + 0.5f) * float(frame.width - 1) + 0.5f);
        auto y = static_cast<uint32_t>((0.5f - sy * 0.5f) * float(frame.height - 1) + 0.5f);
        return at(x, y);
    }
};

// A 2x2 (or any) RGBA8 image written as PNG next to the glTF files the builder writes (test::write_file's folder),
// so a material can name it by a relative uri.
inline std::string write_test_png(const std::string& name, int width, int height, const std::vector<uint32_t>& rgba8) {
    write_png(temp_dir("files") / name, width, height, rgba8);  // renamed into place whole (core/image/image_io.h)
    return name;
}

// Loads the glTF file alone (no default lights), looks at the z = 0 plane from (0, 0, distance) and renders it on
// `backend` (cpu-ref unless a test asks for another); `edit` may change the scene first (lights, environment,
// ambient light).
template <typename Edit>
ProbeImage render_gltf(const std::filesystem::path& file, Edit edit, uint32_t size = 64, uint32_t depth = 4,
                       const std::string& backend = "cpu-ref") {
    Scene scene;
    load_gltf(file, scene);
    scene.camera.position = {0.0f, 0.0f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.vertical_fov_degrees = 45.0f;
    scene.has_camera = true;
    edit(scene);
    DeviceScene device = build_device_scene(scene, BvhBuildOptions{});
    RenderSettings settings;
    settings.width = size;
    settings.height = size;
    settings.max_depth = depth;
    RenderEngine engine(backend, device);
    return ProbeImage{engine.render(scene.camera, settings)};
}

}  // namespace prism::test
