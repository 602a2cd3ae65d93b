// glTF 2.0 JSON (.gltf) through load_scene. One input holds the JSON, then a "#prism-fuzz-bin" line, then the
// external buffer, written as fuzz.gltf and fuzz.bin (seeds name "fuzz.bin" as buffer 0's uri and tex.png as
// their images); data: URIs work without the second part. Dictionary: fuzz/dict/gltf.dict.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    prism::fuzz::load_two_files(data, size, "#prism-fuzz-bin", "fuzz.gltf", "fuzz.bin");
    return 0;
}
