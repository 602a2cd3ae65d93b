// glTF 2.0 JSON (.gltf) through load_scene. One input holds the JSON, then a "#prism-fuzz-bin" line, then the
// external buffer, written as fuzz.gltf and fuzz.bin (seeds name "fuzz.bin" as buffer 0's uri and tex.png as
// their images); data: URIs work without the second part. Dictionary: fuzz/dict/gltf.dict.
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto& dir = prism::fuzz::scratch_dir();
    const auto files = prism::fuzz::split_two_files(prism::fuzz::as_text(data, size), "#prism-fuzz-bin");
    prism::fuzz::write_file(dir / "fuzz.gltf", files.first);
    std::error_code ignored;
    if (files.found)
        prism::fuzz::write_file(dir / "fuzz.bin", files.second);
    else
        std::filesystem::remove(dir / "fuzz.bin", ignored);
    prism::fuzz::load_and_build(dir / "fuzz.gltf");
    return 0;
}
