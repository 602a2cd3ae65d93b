// Reads glTF accessors into plain arrays: any component type, normalized integers, byteStride, accessors without a
// bufferView (all zeros) and sparse substitution. Every read is bounds-checked against its buffer, so a malformed
// file throws prism::Error "<file>: accessor N: <cause>" instead of reading out of bounds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace prism::gltf {

// The accessor's elements as floats, `components` per element (1 for SCALAR ... 4 for VEC4), normalized integer
// types mapped to [0, 1] / [-1, 1] as the glTF spec says.
struct FloatArray {
    int components = 0;
    size_t count = 0;
    std::vector<float> values;  // count * components

    float at(size_t element, int component) const { return values[element * components + component]; }
};

FloatArray read_floats(const tinygltf::Model& model, int accessor_index, const std::string& file);

// A MAT4 accessor of floats (a skin's inverse bind matrices): 16 components per element, column by column.
FloatArray read_mat4s(const tinygltf::Model& model, int accessor_index, const std::string& file);

// A SCALAR accessor of unsigned integers read exactly (vertex indices).
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int accessor_index, const std::string& file);

}  // namespace prism::gltf
