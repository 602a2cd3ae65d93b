// The implementations of stb_image(_write), tinygltf and tinyobjloader, compiled from Debian's own headers into
// the fuzz build. The shipped prism links Debian's shared libraries, built from these same headers; here the
// definitions live in the executable, so they take precedence over the .so ones and are instrumented: libFuzzer
// sees coverage inside the decoders and ASan checks their reads. Not part of any non-fuzz target.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image.h>
#include <stb_image_write.h>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
