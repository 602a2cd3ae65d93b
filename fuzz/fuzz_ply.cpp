// PLY (ASCII, binary little/big endian, gzip by magic bytes) through load_scene: load_ply, the textures a MeshLab
// TextureFile comment names (the scratch folder holds tex.png), validation, framing, BVH build. Dictionary:
// fuzz/dict/ply.dict.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = prism::fuzz::scratch_dir() / "fuzz.ply";
    prism::fuzz::write_file(path, prism::fuzz::as_text(data, size));
    prism::fuzz::load_and_build(path);
    return 0;
}
