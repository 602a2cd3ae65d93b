// EXT_meshopt_compression (and KHR_meshopt_compression, its ratified form): a bufferView's bytes are stored
// compressed by meshoptimizer's codecs in another buffer, and the view's own buffer is often a "fallback" with a
// byteLength but no data (no uri). Decoding gives the view its bytes back, so the accessors read as usual.
#pragma once

#include <string>

namespace tinygltf {
class Model;
}

namespace prism {

// Decodes every compressed bufferView of `model` into a buffer of its own and points the view at it, checking
// every count, stride, mode and filter against the spec and the compressed bytes against their buffer. Throws
// prism::Error "<file>: bufferView N: <cause>" on a malformed or undecodable view.
void decode_meshopt_buffer_views(tinygltf::Model& model, const std::string& file);

}  // namespace prism
