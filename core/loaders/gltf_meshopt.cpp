#include "core/loaders/gltf_meshopt.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <cmath>
#include <optional>

#include "core/loaders/gltf_compression_json.h"
#include "core/util/error.h"

namespace prism {
namespace {

// The codecs cannot expand data without bound: the vertex codec's densest form is two header bits for a group of
// 16 zero bytes (64:1), the index codecs' a byte a triangle or an index. A view claiming more than this from its
// compressed bytes is malformed, and is refused before anything that size is allocated.
constexpr size_t kMaxExpansion = 64;
constexpr size_t kSmallViewBytes = size_t(1) << 16;

const tinygltf::Value* compression(const tinygltf::BufferView& view) {
    for (const char* name : kMeshoptExtensions)
        if (auto it = view.extensions.find(name); it != view.extensions.end() && it->second.IsObject())
            return &it->second;
    return nullptr;
}

struct Reader {
    const tinygltf::Value& object;
    std::string what;
    const std::string& file;

    size_t number(const char* key, std::optional<size_t> fallback) const {
        if (!object.Has(key)) {
            if (fallback) return *fallback;
            throw file_error(file, what + ": " + key + " is missing");
        }
        const tinygltf::Value& value = object.Get(key);
        double number = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
        if (!(number >= 0.0 && number <= double(UINT32_MAX)) || number != std::floor(number))
            throw file_error(file, what + ": " + key + " is not an integer from 0 to 2^32 - 1");
        return size_t(number);
    }

    std::string text(const char* key, const char* fallback) const {
        if (!object.Has(key)) return fallback;
        const tinygltf::Value& value = object.Get(key);
        if (!value.IsString()) throw file_error(file, what + ": " + key + " is not a string");
        return value.Get<std::string>();
    }
};

bool is_fallback(const tinygltf::Buffer& buffer) {
    for (const char* name : kMeshoptExtensions)
        if (auto it = buffer.extensions.find(name); it != buffer.extensions.end() && it->second.IsObject() &&
                                                    it->second.Has("fallback") && it->second.Get("fallback").IsBool() &&
                                                    it->second.Get("fallback").Get<bool>())
            return true;
    return false;
}

}  // namespace

void decode_meshopt_buffer_views(tinygltf::Model& model, const std::string& file) {
    const size_t file_buffers = model.buffers.size();
    for (size_t v = 0; v < model.bufferViews.size(); ++v) {
        const tinygltf::Value* extension = compression(model.bufferViews[v]);
        if (!extension) {
            const int buffer = model.bufferViews[v].buffer;
            if (buffer >= 0 && size_t(buffer) < file_buffers && is_fallback(model.buffers[buffer]))
                throw file_error(file, "bufferView " + std::to_string(v) +
                                           " is not compressed but reads the meshopt "
                                           "fallback buffer " +
                                           std::to_string(buffer) + ", which holds no data");
            continue;
        }
        Reader read{*extension, "bufferView " + std::to_string(v) + " (meshopt)", file};
        const size_t source = read.number("buffer", std::nullopt);
        const size_t offset = read.number("byteOffset", 0);
        const size_t length = read.number("byteLength", std::nullopt);
        const size_t stride = read.number("byteStride", std::nullopt);
        const size_t count = read.number("count", std::nullopt);
        const std::string mode = read.text("mode", "");
        const std::string filter = read.text("filter", "NONE");
        if (source >= model.buffers.size())
            throw file_error(file, read.what + ": buffer " + std::to_string(source) + " does not exist");
        const std::vector<unsigned char>& encoded = model.buffers[source].data;
        if (offset > encoded.size() || length > encoded.size() - offset)
            throw file_error(file, read.what + ": its compressed bytes lie past the end of buffer " +
                                       std::to_string(source) + " (" + std::to_string(encoded.size()) + " bytes)");

        if (mode == "ATTRIBUTES") {
            if (stride == 0 || stride % 4 != 0 || stride > 256)
                throw file_error(file, read.what + ": byteStride " + std::to_string(stride) +
                                           " for ATTRIBUTES must be a multiple of 4 from 4 to 256");
        } else if (mode == "TRIANGLES" || mode == "INDICES") {
            if (stride != 2 && stride != 4)
                throw file_error(
                    file, read.what + ": byteStride " + std::to_string(stride) + " for " + mode + " must be 2 or 4");
            if (mode == "TRIANGLES" && count % 3 != 0)
                throw file_error(
                    file, read.what + ": count " + std::to_string(count) + " for TRIANGLES is not a multiple of 3");
        } else {
            throw file_error(file, read.what + ": unknown mode \"" + mode + "\"");
        }
        if (filter != "NONE") {
            const bool fits =
                mode == "ATTRIBUTES" && ((filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) ||
                                         (filter == "QUATERNION" && stride == 8) || filter == "EXPONENTIAL");
            if (!fits)
                throw file_error(file, read.what + ": filter " + filter + " does not apply to mode " + mode +
                                           " with byteStride " + std::to_string(stride));
        }
        const size_t decoded_bytes = count * stride;  // both below 2^32: no wrap in size_t
        if (decoded_bytes > kMaxExpansion * length + kSmallViewBytes)
            throw file_error(file, read.what + ": " + std::to_string(decoded_bytes) + " bytes claimed from " +
                                       std::to_string(length) + " compressed, more than the codec can produce");

        tinygltf::Buffer decoded;
        decoded.data.resize(decoded_bytes);
        const unsigned char* bytes = encoded.data() + offset;
        int status = 0;
        if (mode == "ATTRIBUTES")
            status = meshopt_decodeVertexBuffer(decoded.data.data(), count, stride, bytes, length);
        else if (mode == "TRIANGLES")
            status = meshopt_decodeIndexBuffer(decoded.data.data(), count, stride, bytes, length);
        else
            status = meshopt_decodeIndexSequence(decoded.data.data(), count, stride, bytes, length);
        if (status != 0)
            throw file_error(file, read.what + ": its " + mode + " data do not decode (meshoptimizer error " +
                                       std::to_string(status) + ": corrupt, or encoded by a newer codec than " +
                                       "meshoptimizer 0." + std::to_string(MESHOPTIMIZER_VERSION / 10) + " reads)");
        if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data.data(), count, stride);
        if (filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data.data(), count, stride);
        if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data.data(), count, stride);

        model.buffers.push_back(std::move(decoded));
        tinygltf::BufferView& view = model.bufferViews[v];
        view.buffer = static_cast<int>(model.buffers.size() - 1);
        view.byteOffset = 0;
        view.byteLength = decoded_bytes;
        if (mode == "ATTRIBUTES") view.byteStride = stride;
    }
}

}  // namespace prism
