// Binary glTF (.glb: header, JSON chunk, BIN chunk) through load_scene. Dictionary: fuzz/dict/gltf.dict.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = prism::fuzz::scratch_dir() / "fuzz.glb";
    prism::fuzz::write_file(path, prism::fuzz::as_text(data, size));
    prism::fuzz::load_and_build(path);
    return 0;
}
