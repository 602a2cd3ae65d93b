// OBJ + MTL through load_scene. One input holds both files: the OBJ, then a "#prism-fuzz-mtl" line, then the MTL,
// written as fuzz.obj and fuzz.mtl (seeds say "mtllib fuzz.mtl"; tex.png is there for map_Kd).
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    prism::fuzz::load_two_files(data, size, "#prism-fuzz-mtl", "fuzz.obj", "fuzz.mtl");
    return 0;
}
