// Images (PNG, JPEG, TGA, BMP, Radiance .hdr, whatever stb_image recognises) through the loaders that read image
// files: textures, cube-map faces and equirect maps all reach load_texture -> load_texture_from_memory. The input
// becomes the +X face of a cube map whose other faces are the fixtures (even sizes) or an equirect map (odd
// sizes); the environment then goes through validation and the device arrays, as a render would take it.
#include "fuzz/fuzz_support.h"

#include "core/render/device_scene.h"
#include "core/loaders/environment_maps.h"
#include "core/loaders/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto& dir = prism::fuzz::scratch_dir();
    const bool cube_map = size % 2 == 0;
    const auto path = cube_map ? dir / "sky" / "right.png" : dir / "equirect.hdr";
    prism::fuzz::write_file(path, prism::fuzz::as_text(data, size));
    prism::fuzz::expect_clean_outcome([&] {
        prism::Scene scene;
        scene.source = path.string();
        prism::Mesh triangle;
        triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        triangle.triangles = {{0, 1, 2}};
        triangle.triangle_materials = {0};
        scene.meshes.push_back(triangle);
        scene.instances.push_back(prism::Instance{});
        scene.materials.push_back(prism::Material{});
        if (cube_map)
            prism::load_cube_map(dir / "sky", scene);
        else
            prism::load_equirect_map(path, scene);
        prism::validate_scene(scene);
        (void)prism::build_device_scene(scene);
    });
    return 0;
}
