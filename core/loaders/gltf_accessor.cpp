#include "core/loaders/gltf_accessor.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>

#include <tiny_gltf.h>

#include "core/util/error.h"

namespace prism::gltf {
namespace {

int component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

int component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;  // matrices are never vertex attributes Prism reads
    }
}

template <typename T>
T load_unaligned(const uint8_t* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));  // glTF allows strides that leave elements unaligned
    return value;
}

// Normalized integers follow the glTF spec: unsigned c / max, signed max(c / max, -1).
template <typename T>
double integer(const uint8_t* bytes, bool normalized) {
    double c = load_unaligned<T>(bytes);
    if (!normalized) return c;
    double scaled = c / static_cast<double>(std::numeric_limits<T>::max());
    return std::is_signed_v<T> ? std::max(scaled, -1.0) : scaled;
}

double decode(const uint8_t* bytes, int component_type, bool normalized) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return integer<int8_t>(bytes, normalized);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return integer<uint8_t>(bytes, normalized);
        case TINYGLTF_COMPONENT_TYPE_SHORT: return integer<int16_t>(bytes, normalized);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return integer<uint16_t>(bytes, normalized);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return integer<uint32_t>(bytes, normalized);
        default: return load_unaligned<float>(bytes);
    }
}

// Where a run of `count` elements of `element_size` bytes, `stride` apart, starts inside its buffer; throws when
// any byte of the run lies outside the bufferView or the buffer.
const uint8_t* locate(const tinygltf::Model& model, int buffer_view_index, size_t byte_offset, size_t count,
                      size_t element_size, size_t stride, const std::string& what, const std::string& file) {
    if (buffer_view_index < 0 || buffer_view_index >= static_cast<int>(model.bufferViews.size()))
        throw file_error(file, what + ": bufferView " + std::to_string(buffer_view_index) + " does not exist");
    const tinygltf::BufferView& view = model.bufferViews[buffer_view_index];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
        throw file_error(file, what + ": buffer " + std::to_string(view.buffer) + " does not exist");
    const tinygltf::Buffer& buffer = model.buffers[view.buffer];
    if (count == 0) return buffer.data.data();
    // Written so that no product or sum can wrap around, whatever counts and offsets the file claims.
    const size_t length = view.byteLength;
    const bool view_inside_buffer =
        view.byteOffset <= buffer.data.size() && length <= buffer.data.size() - view.byteOffset;
    const bool run_inside_view = byte_offset <= length && element_size <= length - byte_offset &&
                                 count - 1 <= (length - byte_offset - element_size) / stride;
    if (!view_inside_buffer || !run_inside_view)
        throw file_error(file,
                         what + " reads past the end of its buffer (" + std::to_string(buffer.data.size()) + " bytes)");
    return buffer.data.data() + view.byteOffset + byte_offset;
}

// Reads every component of every element as double (exact for all glTF integer types), then applies sparse
// substitution. Doubles keep one code path for indices and attributes; the arrays are transient.
std::vector<double> read_components(const tinygltf::Model& model, int accessor_index, const std::string& file,
                                    int& components_out, bool normalized_allowed, bool matrices_allowed = false) {
    std::string what = "accessor " + std::to_string(accessor_index);
    if (accessor_index < 0 || accessor_index >= static_cast<int>(model.accessors.size()))
        throw file_error(file, what + " does not exist");
    const tinygltf::Accessor& accessor = model.accessors[accessor_index];
    int size = component_size(accessor.componentType);
    int components = component_count(accessor.type);
    if (matrices_allowed && accessor.type == TINYGLTF_TYPE_MAT4) components = 16;
    if (size == 0) throw file_error(file, what + ": unknown componentType " + std::to_string(accessor.componentType));
    if (components == 0) throw file_error(file, what + ": unsupported type (matrix accessor used as an attribute)");
    bool normalized = accessor.normalized && normalized_allowed;

    // Every count is checked against the bytes behind it before anything is allocated: 2^31 indices claimed over
    // a 12-byte bufferView must fail here, not after gigabytes of doubles.
    size_t element_size = static_cast<size_t>(size) * components;
    const uint8_t* base = nullptr;
    size_t stride = element_size;
    if (accessor.bufferView >= 0) {
        if (accessor.bufferView >= static_cast<int>(model.bufferViews.size()))
            throw file_error(file, what + ": bufferView " + std::to_string(accessor.bufferView) + " does not exist");
        const tinygltf::BufferView& view = model.bufferViews[accessor.bufferView];
        stride = view.byteStride ? view.byteStride : element_size;
        if (stride < element_size) throw file_error(file, what + ": byteStride smaller than one element");
        base =
            locate(model, accessor.bufferView, accessor.byteOffset, accessor.count, element_size, stride, what, file);
    } else {
        // No bufferView: zeros (spec), perhaps with sparse values. Nothing backs the count, so it may not exceed
        // what the file's buffers could hold as elements of this type, or a few thousand elements, which a file
        // without any buffer may zero-fill too (memory stays bounded either way).
        constexpr size_t kZeroElementsAnyFileMay = 4096;
        size_t buffer_bytes = 0;
        for (const tinygltf::Buffer& buffer : model.buffers) buffer_bytes += buffer.data.size();
        if (accessor.count > std::max(buffer_bytes / element_size, kZeroElementsAnyFileMay))
            throw file_error(file, what + ": count " + std::to_string(accessor.count) +
                                       " without a bufferView is more than the file's buffers (" +
                                       std::to_string(buffer_bytes) + " bytes) hold");
    }
    std::vector<double> values(accessor.count * components, 0.0);
    if (base)
        for (size_t i = 0; i < accessor.count; ++i)
            for (int c = 0; c < components; ++c)
                values[i * components + c] = decode(base + i * stride + c * size, accessor.componentType, normalized);

    if (accessor.sparse.isSparse) {
        const auto& sparse = accessor.sparse;
        if (sparse.count < 0) throw file_error(file, what + ": negative sparse count");
        size_t sparse_count = static_cast<size_t>(sparse.count);
        int index_size = component_size(sparse.indices.componentType);
        if (index_size == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
            sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
            sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
            throw file_error(file, what + ": sparse indices must be unsigned integers");
        const uint8_t* indices = locate(model, sparse.indices.bufferView, sparse.indices.byteOffset, sparse_count,
                                        index_size, index_size, what + " sparse indices", file);
        const uint8_t* substitutes = locate(model, sparse.values.bufferView, sparse.values.byteOffset, sparse_count,
                                            element_size, element_size, what + " sparse values", file);
        for (size_t i = 0; i < sparse_count; ++i) {
            auto target = static_cast<size_t>(decode(indices + i * index_size, sparse.indices.componentType, false));
            if (target >= accessor.count)
                throw file_error(file, what + ": sparse index " + std::to_string(target) + " out of range (count " +
                                           std::to_string(accessor.count) + ")");
            for (int c = 0; c < components; ++c)
                values[target * components + c] =
                    decode(substitutes + i * element_size + c * size, accessor.componentType, normalized);
        }
    }
    components_out = components;
    return values;
}

}  // namespace

FloatArray read_floats(const tinygltf::Model& model, int accessor_index, const std::string& file) {
    FloatArray array;
    std::vector<double> values = read_components(model, accessor_index, file, array.components, true);
    array.values.assign(values.begin(), values.end());
    array.count = array.components ? values.size() / array.components : 0;
    return array;
}

FloatArray read_mat4s(const tinygltf::Model& model, int accessor_index, const std::string& file) {
    FloatArray array;
    std::vector<double> values = read_components(model, accessor_index, file, array.components, false, true);
    const tinygltf::Accessor& accessor = model.accessors[accessor_index];
    if (array.components != 16 || accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw file_error(file, "accessor " + std::to_string(accessor_index) + ": must be MAT4 of floats");
    array.values.assign(values.begin(), values.end());
    array.count = values.size() / 16;
    return array;
}

std::vector<uint32_t> read_indices(const tinygltf::Model& model, int accessor_index, const std::string& file) {
    int components = 0;
    std::vector<double> values = read_components(model, accessor_index, file, components, false);
    const tinygltf::Accessor& accessor = model.accessors[accessor_index];
    if (components != 1 || accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw file_error(file,
                         "accessor " + std::to_string(accessor_index) + ": indices must be SCALAR unsigned integers");
    std::vector<uint32_t> indices(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
        if (values[i] < 0) throw file_error(file, "accessor " + std::to_string(accessor_index) + ": negative index");
        indices[i] = static_cast<uint32_t>(values[i]);
    }
    return indices;
}

}  // namespace prism::gltf
