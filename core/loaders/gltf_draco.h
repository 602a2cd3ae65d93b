// KHR_draco_mesh_compression: a primitive's attributes and indices stored as one Draco-compressed bufferView, its
// accessors without data of their own. Decoding writes them out as plain buffers, so the importer reads a Draco
// primitive as it reads any other.
#pragma once

#include <string>

namespace tinygltf {
class Model;
}

namespace prism {

// Decodes every Draco-compressed triangle primitive of `model`: each attribute the extension names, and the
// faces, go into a new buffer and bufferView, and the primitive's accessors point at them (FLOAT attributes,
// UNSIGNED_INT indices; an index accessor is added when the primitive has none). The extension is then removed
// from the primitive. Throws prism::Error "<file>: mesh M primitive P: <cause>" when the data do not decode or do
// not fit the accessors.
void decode_draco_primitives(tinygltf::Model& model, const std::string& file);

}  // namespace prism
