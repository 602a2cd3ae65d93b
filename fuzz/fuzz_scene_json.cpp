// Prism scene files (.json) through load_scene: load_scene_json, and through it the model loaders, textures, cube
// and equirect maps it names. The scratch folder's fixtures (tri.ply, tri.obj, tri.gltf, tex.png, sky/, sky.hdr)
// are what inputs can place. Dictionary: fuzz/dict/scene_json.dict.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = prism::fuzz::scratch_dir() / "fuzz.json";
    prism::fuzz::write_file(path, prism::fuzz::as_text(data, size));
    prism::fuzz::load_and_build(path);
    return 0;
}
