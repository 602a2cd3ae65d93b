// OBJ + MTL through load_scene. One input holds both files: the OBJ, then a "#prism-fuzz-mtl" line, then the MTL,
// written as fuzz.obj and fuzz.mtl (seeds say "mtllib fuzz.mtl"; tex.png is there for map_Kd).
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto& dir = prism::fuzz::scratch_dir();
    const auto files = prism::fuzz::split_two_files(prism::fuzz::as_text(data, size), "#prism-fuzz-mtl");
    prism::fuzz::write_file(dir / "fuzz.obj", files.first);
    std::error_code ignored;
    if (files.found)
        prism::fuzz::write_file(dir / "fuzz.mtl", files.second);
    else
        std::filesystem::remove(dir / "fuzz.mtl", ignored);  // a missing MTL is an input too
    prism::fuzz::load_and_build(dir / "fuzz.obj");
    return 0;
}
