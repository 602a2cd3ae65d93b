#include "core/loaders/gltf_draco.h"

#include <draco/compression/decode.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/loaders/gltf_compression_json.h"
#include "core/util/error.h"

namespace prism {
namespace {

int accessor_components(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

int integer_in(const tinygltf::Value& object, const char* key) {
    if (!object.Has(key) || !object.Get(key).IsNumber()) return -1;
    double number = object.Get(key).GetNumberAsDouble();
    return number >= 0.0 && number < double(INT32_MAX) && number == std::floor(number) ? int(number) : -1;
}

// A new buffer holding `bytes` and a tightly packed view of it; returns the view's index.
int add_view(tinygltf::Model& model, std::vector<unsigned char> bytes) {
    tinygltf::BufferView view;
    view.buffer = static_cast<int>(model.buffers.size());
    view.byteOffset = 0;
    view.byteLength = bytes.size();
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes);
    model.buffers.push_back(std::move(buffer));
    model.bufferViews.push_back(std::move(view));
    return static_cast<int>(model.bufferViews.size() - 1);
}

void point_accessor_at(tinygltf::Accessor& accessor, int view, int component_type, size_t count) {
    accessor.bufferView = view;
    accessor.byteOffset = 0;
    accessor.componentType = component_type;
    accessor.normalized = false;
    accessor.count = count;
    accessor.sparse.isSparse = false;  // the decoded values are the whole data
    accessor.minValues.clear();
    accessor.maxValues.clear();
}

class DracoPrimitive {
public:
    DracoPrimitive(tinygltf::Model& model, tinygltf::Primitive& primitive, std::string what, const std::string& file)
        : model_(model), primitive_(primitive), what_(std::move(what)), file_(file) {}

    void decode(const tinygltf::Value& extension) {
        if (primitive_.mode != TINYGLTF_MODE_TRIANGLES)
            throw error("a Draco mesh is a triangle list, and this primitive's mode is " +
                        std::to_string(primitive_.mode));
        std::unique_ptr<draco::Mesh> mesh = decode_mesh(extension);
        const tinygltf::Value& ids = extension.Get("attributes");
        if (!ids.IsObject()) throw error("its Draco extension has no attributes object");
        for (const std::string& name : ids.Keys()) {
            auto accessor = primitive_.attributes.find(name);
            if (accessor == primitive_.attributes.end()) continue;  // an attribute the primitive does not use
            int id = integer_in(ids, name.c_str());
            const draco::PointAttribute* attribute = id < 0 ? nullptr : mesh->GetAttributeByUniqueId(uint32_t(id));
            if (!attribute) throw error("Draco attribute " + name + " (id " + std::to_string(id) + ") is missing");
            write_attribute(name, accessor->second, *mesh, *attribute);
        }
        write_indices(*mesh);
    }

private:
    Error error(const std::string& cause) const { return file_error(file_, what_ + ": " + cause); }

    std::unique_ptr<draco::Mesh> decode_mesh(const tinygltf::Value& extension) {
        int view_index = integer_in(extension, "bufferView");
        if (view_index < 0 || view_index >= static_cast<int>(model_.bufferViews.size()))
            throw error("its Draco extension names no bufferView that exists");
        const tinygltf::BufferView& view = model_.bufferViews[view_index];
        if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size()))
            throw error("the Draco bufferView's buffer " + std::to_string(view.buffer) + " does not exist");
        const std::vector<unsigned char>& bytes = model_.buffers[view.buffer].data;
        if (view.byteOffset > bytes.size() || view.byteLength > bytes.size() - view.byteOffset)
            throw error("the Draco data lie past the end of buffer " + std::to_string(view.buffer) + " (" +
                        std::to_string(bytes.size()) + " bytes)");
        draco::DecoderBuffer buffer;
        buffer.Init(reinterpret_cast<const char*>(bytes.data() + view.byteOffset), view.byteLength);
        draco::Decoder decoder;
        auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
        if (!decoded.ok()) throw error("its Draco data do not decode (" + decoded.status().error_msg_string() + ")");
        std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
        if (!mesh) throw error("its Draco data hold no mesh");
        return mesh;
    }

    void write_attribute(const std::string& name, int accessor_index, const draco::Mesh& mesh,
                         const draco::PointAttribute& attribute) {
        if (accessor_index < 0 || accessor_index >= static_cast<int>(model_.accessors.size()))
            throw error(name + ": accessor " + std::to_string(accessor_index) + " does not exist");
        tinygltf::Accessor& accessor = model_.accessors[accessor_index];
        const int components = accessor_components(accessor.type);
        if (components == 0) throw error(name + ": accessor " + std::to_string(accessor_index) + " is a matrix");
        // A normalized integer accessor whose Draco attribute does not carry the flag: scale as the accessor says.
        float scale = 1.0f;
        if (accessor.normalized && !attribute.normalized()) {
            switch (attribute.data_type()) {
                case draco::DT_UINT8: scale = 1.0f / 255.0f; break;
                case draco::DT_INT8: scale = 1.0f / 127.0f; break;
                case draco::DT_UINT16: scale = 1.0f / 65535.0f; break;
                case draco::DT_INT16: scale = 1.0f / 32767.0f; break;
                default: break;
            }
        }
        const size_t points = mesh.num_points();
        std::vector<unsigned char> bytes(points * components * sizeof(float));
        std::vector<float> value(components);
        for (size_t p = 0; p < points; ++p) {
            const draco::AttributeValueIndex index = attribute.mapped_index(draco::PointIndex(uint32_t(p)));
            if (index.value() >= attribute.size() ||
                !attribute.ConvertValue<float>(index, int8_t(components), value.data()))
                throw error(name + ": Draco value " + std::to_string(p) + " does not convert to float");
            if (scale != 1.0f)
                for (float& component : value) component = std::max(-1.0f, component * scale);  // spec's clamp
            std::memcpy(bytes.data() + p * components * sizeof(float), value.data(), components * sizeof(float));
        }
        point_accessor_at(accessor, add_view(model_, std::move(bytes)), TINYGLTF_COMPONENT_TYPE_FLOAT, points);
    }

    void write_indices(const draco::Mesh& mesh) {
        const size_t faces = mesh.num_faces();
        std::vector<unsigned char> bytes(faces * 3 * sizeof(uint32_t));
        for (size_t f = 0; f < faces; ++f) {
            const draco::Mesh::Face& face = mesh.face(draco::FaceIndex(uint32_t(f)));
            const uint32_t corners[3] = {face[0].value(), face[1].value(), face[2].value()};
            std::memcpy(bytes.data() + f * sizeof(corners), corners, sizeof(corners));
        }
        if (primitive_.indices < 0 || primitive_.indices >= static_cast<int>(model_.accessors.size())) {
            tinygltf::Accessor indices;
            indices.type = TINYGLTF_TYPE_SCALAR;
            model_.accessors.push_back(std::move(indices));
            primitive_.indices = static_cast<int>(model_.accessors.size() - 1);
        }
        tinygltf::Accessor& accessor = model_.accessors[primitive_.indices];
        accessor.type = TINYGLTF_TYPE_SCALAR;
        point_accessor_at(accessor, add_view(model_, std::move(bytes)), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                          faces * 3);
    }

    tinygltf::Model& model_;
    tinygltf::Primitive& primitive_;
    std::string what_;
    const std::string& file_;
};

}  // namespace

void decode_draco_primitives(tinygltf::Model& model, const std::string& file) {
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive& primitive = model.meshes[m].primitives[p];
            auto extension = primitive.extensions.find(kDracoExtension);
            // Points and lines (Draco point clouds among them) are not traced: the importer skips them.
            if (extension == primitive.extensions.end() || primitive.mode == TINYGLTF_MODE_POINTS ||
                primitive.mode == TINYGLTF_MODE_LINE || primitive.mode == TINYGLTF_MODE_LINE_LOOP ||
                primitive.mode == TINYGLTF_MODE_LINE_STRIP)
                continue;
            if (!extension->second.IsObject())
                throw file_error(file, "mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ": " +
                                           kDracoExtension + " is not an object");
            tinygltf::Value settings = extension->second;
            primitive.extensions.erase(extension);
            DracoPrimitive(model, primitive, "mesh " + std::to_string(m) + " primitive " + std::to_string(p), file)
                .decode(settings);
        }
    }
}

}  // namespace prism
