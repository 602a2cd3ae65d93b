// Writes a mesh as a compressed .gltf: Draco (KHR_draco_mesh_compression) or meshoptimizer
// (EXT_meshopt_compression) — the encoders' own output, so the tests and the fuzz seeds check the loader against
// files the libraries make, from any mesh they load (the shared scenes' real models among them).
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "core/scene/scene.h"
#include "tests/gltf_builder.h"

namespace prism::test {

// A triangle list as glTF stores it: positions and optional normals and texture coordinates per vertex.
struct PlainMesh {
    std::vector<float> positions;  // xyz per vertex
    std::vector<float> normals;    // xyz per vertex, or empty
    std::vector<float> uv;         // uv per vertex, or empty
    std::vector<uint32_t> indices;
    size_t vertex_count() const { return positions.size() / 3; }
};

inline PlainMesh plain_mesh(const Mesh& mesh) {
    PlainMesh plain;
    for (const glm::vec3& p : mesh.positions) plain.positions.insert(plain.positions.end(), {p.x, p.y, p.z});
    for (const glm::vec3& n : mesh.normals) plain.normals.insert(plain.normals.end(), {n.x, n.y, n.z});
    for (const glm::vec2& uv : mesh.uv0) plain.uv.insert(plain.uv.end(), {uv.x, uv.y});
    for (const glm::uvec3& t : mesh.triangles) plain.indices.insert(plain.indices.end(), {t.x, t.y, t.z});
    return plain;
}

// A .gltf document whose buffer 0 is `buffer`, not yet written into it (the fuzz seeds append it as a file).
struct CompressedGltf {
    nlohmann::json document;
    std::string buffer;

    // The .gltf text with buffer 0 embedded as a base64 data URI.
    std::string embedded() const {
        nlohmann::json out = document;
        out["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(buffer);
        return out.dump(1);
    }
};

inline nlohmann::json gltf_around(nlohmann::json primitive) {
    // One-element arrays spelled out: a braced single json value is an array to GCC and a copy to clang.
    using json = nlohmann::json;
    json mesh = {{"primitives", json::array({std::move(primitive)})}};
    json node = {{"mesh", 0}};
    json scene = {{"nodes", json::array({0})}};
    return {{"asset", {{"version", "2.0"}}},
            {"meshes", json::array({mesh})},
            {"nodes", json::array({node})},
            {"scenes", json::array({scene})},
            {"scene", 0}};
}

inline nlohmann::json float_accessor(size_t count, const char* type) {
    return {{"componentType", 5126}, {"count", count}, {"type", type}};
}

// Draco's edgebreaker connectivity with its default attribute encoding (no quantization unless `position_bits`):
// vertex and corner order change, the geometry does not.
inline CompressedGltf draco_gltf(const PlainMesh& plain, int position_bits = 0) {
    draco::Mesh mesh;
    const size_t n = plain.vertex_count();
    mesh.set_num_points(static_cast<uint32_t>(n));
    auto add = [&](draco::GeometryAttribute::Type type, const std::vector<float>& values, int components) {
        if (values.empty()) return -1;
        draco::GeometryAttribute attribute;
        attribute.Init(type, nullptr, components, draco::DT_FLOAT32, false, sizeof(float) * components, 0);
        int id = mesh.AddAttribute(attribute, true, static_cast<uint32_t>(n));
        for (size_t i = 0; i < n; ++i)
            mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &values[i * components]);
        return id;
    };
    const int position = add(draco::GeometryAttribute::POSITION, plain.positions, 3);
    const int normal = add(draco::GeometryAttribute::NORMAL, plain.normals, 3);
    const int uv = add(draco::GeometryAttribute::TEX_COORD, plain.uv, 2);
    for (size_t t = 0; t + 2 < plain.indices.size(); t += 3)
        mesh.AddFace({draco::PointIndex(plain.indices[t]), draco::PointIndex(plain.indices[t + 1]),
                      draco::PointIndex(plain.indices[t + 2])});
    draco::Encoder encoder;
    if (position_bits) encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, position_bits);
    draco::EncoderBuffer encoded;
    if (!encoder.EncodeMeshToBuffer(mesh, &encoded).ok()) throw std::runtime_error("Draco encoding failed");
    const std::string bytes(encoded.data(), encoded.size());

    nlohmann::json attributes = {{"POSITION", 0}}, ids = {{"POSITION", mesh.attribute(position)->unique_id()}};
    nlohmann::json accessors = nlohmann::json::array({float_accessor(n, "VEC3")});
    if (normal >= 0) {
        attributes["NORMAL"] = accessors.size();
        ids["NORMAL"] = mesh.attribute(normal)->unique_id();
        accessors.push_back(float_accessor(n, "VEC3"));
    }
    if (uv >= 0) {
        attributes["TEXCOORD_0"] = accessors.size();
        ids["TEXCOORD_0"] = mesh.attribute(uv)->unique_id();
        accessors.push_back(float_accessor(n, "VEC2"));
    }
    const size_t indices = accessors.size();
    accessors.push_back({{"componentType", 5125}, {"count", plain.indices.size()}, {"type", "SCALAR"}});
    nlohmann::json gltf =
        gltf_around({{"attributes", attributes},
                     {"indices", indices},
                     {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", ids}}}}}});
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = nlohmann::json::array({{{"buffer", 0}, {"byteLength", bytes.size()}}});
    gltf["buffers"] = nlohmann::json::array({{{"byteLength", bytes.size()}}});
    gltf["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    gltf["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    return {gltf, bytes};
}

// Every stream compressed with meshoptimizer's codecs into buffer 0; buffer 1 is the fallback without data that
// gltfpack writes. Positions and texture coordinates are stored exactly; normals exactly too, or as 16-bit
// octahedral vectors (the OCTAHEDRAL filter, normalized SHORT x4 with KHR_mesh_quantization) when `octahedral`.
inline CompressedGltf meshopt_gltf(const PlainMesh& plain, bool octahedral = false) {
    const size_t n = plain.vertex_count();
    std::string compressed;
    nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
    size_t fallback_bytes = 0;
    auto add_view = [&](const void* data, size_t count, size_t stride, const char* mode, const char* filter) {
        std::vector<unsigned char> out;
        size_t size = 0;
        if (std::strcmp(mode, "ATTRIBUTES") == 0) {
            out.resize(meshopt_encodeVertexBufferBound(count, stride));
            size = meshopt_encodeVertexBuffer(out.data(), out.size(), data, count, stride);
        } else {
            out.resize(meshopt_encodeIndexBufferBound(count, n));
            size = meshopt_encodeIndexBuffer(out.data(), out.size(), static_cast<const unsigned*>(data), count);
        }
        while (compressed.size() % 4) compressed.push_back('\0');
        nlohmann::json extension = {{"buffer", 0},        {"byteOffset", compressed.size()},
                                    {"byteLength", size}, {"byteStride", stride},
                                    {"count", count},     {"mode", mode}};
        if (std::strcmp(filter, "NONE") != 0) extension["filter"] = filter;
        compressed.append(reinterpret_cast<const char*>(out.data()), size);
        nlohmann::json view = {{"buffer", 1},
                               {"byteOffset", fallback_bytes},
                               {"byteLength", count * stride},
                               {"extensions", {{"EXT_meshopt_compression", extension}}}};
        if (std::strcmp(mode, "ATTRIBUTES") == 0) view["byteStride"] = stride;
        fallback_bytes += (count * stride + 3) / 4 * 4;
        views.push_back(view);
        return views.size() - 1;
    };
    nlohmann::json attributes;
    auto add_accessor = [&](nlohmann::json accessor) {
        accessors.push_back(std::move(accessor));
        return accessors.size() - 1;
    };
    nlohmann::json position = float_accessor(n, "VEC3");
    position["bufferView"] = add_view(plain.positions.data(), n, 12, "ATTRIBUTES", "NONE");
    attributes["POSITION"] = add_accessor(position);
    if (!plain.normals.empty()) {
        if (octahedral) {
            std::vector<float> xyzw(n * 4, 0.0f);
            for (size_t i = 0; i < n; ++i) std::memcpy(&xyzw[i * 4], &plain.normals[i * 3], 3 * sizeof(float));
            std::vector<int16_t> packed(n * 4);
            meshopt_encodeFilterOct(packed.data(), n, 8, 16, xyzw.data());
            attributes["NORMAL"] =
                add_accessor({{"componentType", 5122},
                              {"normalized", true},
                              {"count", n},
                              {"type", "VEC3"},
                              {"bufferView", add_view(packed.data(), n, 8, "ATTRIBUTES", "OCTAHEDRAL")}});
        } else {
            nlohmann::json normal = float_accessor(n, "VEC3");
            normal["bufferView"] = add_view(plain.normals.data(), n, 12, "ATTRIBUTES", "NONE");
            attributes["NORMAL"] = add_accessor(normal);
        }
    }
    if (!plain.uv.empty()) {
        nlohmann::json uv = float_accessor(n, "VEC2");
        uv["bufferView"] = add_view(plain.uv.data(), n, 8, "ATTRIBUTES", "NONE");
        attributes["TEXCOORD_0"] = add_accessor(uv);
    }
    const size_t indices =
        add_accessor({{"componentType", 5125},
                      {"count", plain.indices.size()},
                      {"type", "SCALAR"},
                      {"bufferView", add_view(plain.indices.data(), plain.indices.size(), 4, "TRIANGLES", "NONE")}});
    nlohmann::json gltf = gltf_around({{"attributes", attributes}, {"indices", indices}});
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = views;
    gltf["buffers"] = {
        {{"byteLength", compressed.size()}},
        {{"byteLength", fallback_bytes}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
    gltf["extensionsUsed"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
    gltf["extensionsRequired"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
    return {gltf, compressed};
}

}  // namespace prism::test
