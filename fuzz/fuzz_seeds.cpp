// fuzz_seeds SCENES_DIR REPO_DIR OUT_DIR: writes one seed folder per fuzz target under OUT_DIR, derived at run
// time from the shared scenes (never copied into the repository): small real files as they are, and small
// derivatives of the big ones (a patch of the Stanford bunny in every PLY encoding, real MTL files on a textured
// triangle, glTF JSON with its buffer appended, Draco and meshopt files the encoders make, images scaled down and
// re-encoded in every format stb writes and as WebP). Small seeds keep executions fast; libFuzzer's mutations and the
// dictionaries do the rest.
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb_image.h>
#include <stb_image_write.h>
#include <webp/encode.h>
#include <zlib.h>

#include "core/image/image_io.h"
#include "core/loaders/glb_container.h"
#include "core/loaders/load_ply.h"
#include "fuzz/fuzz_support.h"
#include "tests/gltf_compressed.h"
#include "tests/hostile_files.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr size_t kMaxSeedBytes = 64 * 1024;  // larger real files are left out (or shrunk, below)

std::string read_file(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    std::stringstream bytes;
    bytes << file.rdbuf();
    return bytes.str();
}

std::vector<fs::path> files_with(const fs::path& root, std::set<std::string> extensions) {
    std::vector<fs::path> found;
    std::error_code error;
    for (fs::recursive_directory_iterator it(root, error), end; !error && it != end; it.increment(error)) {
        std::string extension = it->path().extension().string();
        for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (it->is_regular_file() && extensions.count(extension)) found.push_back(it->path());
    }
    std::sort(found.begin(), found.end());
    return found;
}

class SeedWriter {
public:
    explicit SeedWriter(fs::path out) : out_(std::move(out)) {}

    void add(const std::string& target, const std::string& name, std::string_view bytes) {
        if (bytes.size() > kMaxSeedBytes) return;
        fs::create_directories(out_ / target);
        prism::fuzz::write_file(out_ / target / name, bytes);
        ++counts_[target];
    }
    void report() const {
        for (const auto& [target, count] : counts_) std::printf("  %-12s %zu seeds\n", target.c_str(), count);
    }

private:
    fs::path out_;
    std::map<std::string, size_t> counts_;
};

// ---- PLY: a patch of a real scan in each encoding and property layout the reader supports --------------------

prism::Mesh patch_of(const prism::Mesh& mesh, size_t triangles) {
    prism::Mesh patch;
    std::map<uint32_t, uint32_t> remap;
    for (size_t t = 0; t < std::min(triangles, mesh.triangles.size()); ++t) {
        glm::uvec3 out;
        for (int c = 0; c < 3; ++c) {
            auto [entry, inserted] = remap.try_emplace(mesh.triangles[t][c], uint32_t(patch.positions.size()));
            if (inserted) {
                patch.positions.push_back(mesh.positions[entry->first]);
                patch.normals.push_back(mesh.normals[entry->first]);
            }
            out[c] = entry->second;
        }
        patch.triangles.push_back(out);
    }
    return patch;
}

template <typename T>
void put(std::string& bytes, T value, bool big_endian) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian) std::reverse(raw, raw + sizeof(T));
    bytes.append(raw, sizeof(T));
}

enum class PlyFormat { Ascii, Little, Big };

std::string write_ply(const prism::Mesh& mesh, PlyFormat format, bool extras) {
    const char* names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    std::string text = "ply\nformat " + std::string(names[int(format)]) + " 1.0\ncomment derived from a scan\n";
    text += "element vertex " + std::to_string(mesh.positions.size()) + "\n";
    text += extras ? "property double x\nproperty double y\nproperty double z\n"
                   : "property float x\nproperty float y\nproperty float z\n";
    if (extras)
        text +=
            "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
            "property uchar blue\nproperty float u\nproperty float v\nproperty float confidence\n";
    text += "element face " + std::to_string(mesh.triangles.size()) + "\n";
    text += extras ? "property list uint int vertex_index\nproperty uchar flags\n"
                   : "property list uchar int vertex_indices\n";
    if (extras) text += "element edge 1\nproperty int vertex1\nproperty int vertex2\n";
    text += "end_header\n";
    const bool big = format == PlyFormat::Big;
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::vec3 p = mesh.positions[v], n = mesh.normals[v];
        const int colour[3] = {int(v * 37 % 256), int(v * 91 % 256), int(v * 13 % 256)};
        if (format == PlyFormat::Ascii) {
            char line[256];
            std::snprintf(line, sizeof line, "%g %g %g", p.x, p.y, p.z);
            text += line;
            if (extras) {
                std::snprintf(line, sizeof line, " %g %g %g %d %d %d %g %g 1", n.x, n.y, n.z, colour[0], colour[1],
                              colour[2], p.x * 10, p.y * 10);
                text += line;
            }
            text += "\n";
            continue;
        }
        for (int c = 0; c < 3; ++c) extras ? put<double>(text, p[c], big) : put<float>(text, p[c], big);
        if (!extras) continue;
        for (int c = 0; c < 3; ++c) put<float>(text, n[c], big);
        for (int c = 0; c < 3; ++c) put<uint8_t>(text, uint8_t(colour[c]), big);
        put<float>(text, p.x * 10, big);
        put<float>(text, p.y * 10, big);
        put<float>(text, 1.0f, big);
    }
    for (const glm::uvec3& t : mesh.triangles) {
        if (format == PlyFormat::Ascii) {
            text += "3 " + std::to_string(t.x) + " " + std::to_string(t.y) + " " + std::to_string(t.z);
            text += extras ? " 0\n" : "\n";
            continue;
        }
        extras ? put<uint32_t>(text, 3, big) : put<uint8_t>(text, 3, big);
        for (int c = 0; c < 3; ++c) put<int32_t>(text, int32_t(t[c]), big);
        if (extras) put<uint8_t>(text, 0, big);
    }
    if (extras) text += format == PlyFormat::Ascii ? "0 1\n" : std::string(8, '\0');
    return text;
}

// MeshLab's textured PLY: a TextureFile comment naming the scratch folder's tex.png, per-corner texcoord lists, a
// texnumber per face (core/loaders/load_ply.cpp FaceLayout).
std::string write_meshlab_ply(const prism::Mesh& mesh, PlyFormat format) {
    const char* names[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    std::string text = "ply\nformat " + std::string(names[int(format)]) +
                       " 1.0\ncomment VCGLIB generated\ncomment TextureFile tex.png\nelement vertex " +
                       std::to_string(mesh.positions.size()) +
                       "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                       std::to_string(mesh.triangles.size()) +
                       "\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
                       "property int texnumber\nend_header\n";
    const bool big = format == PlyFormat::Big;
    for (const glm::vec3& p : mesh.positions) {
        if (format == PlyFormat::Ascii) {
            char line[128];
            std::snprintf(line, sizeof line, "%g %g %g\n", p.x, p.y, p.z);
            text += line;
        } else {
            for (int c = 0; c < 3; ++c) put<float>(text, p[c], big);
        }
    }
    for (const glm::uvec3& t : mesh.triangles) {
        const float uv[6] = {0.0f, 0.0f, 1.0f, 0.0f, float(t.x % 7) / 7.0f, 1.0f};
        if (format == PlyFormat::Ascii) {
            char line[160];
            std::snprintf(line, sizeof line, "3 %u %u %u 6 %g %g %g %g %g %g 0\n", t.x, t.y, t.z, uv[0], uv[1], uv[2],
                          uv[3], uv[4], uv[5]);
            text += line;
            continue;
        }
        put<uint8_t>(text, 3, big);
        for (int c = 0; c < 3; ++c) put<int32_t>(text, int32_t(t[c]), big);
        put<uint8_t>(text, 6, big);
        for (float value : uv) put<float>(text, value, big);
        put<int32_t>(text, 0, big);
    }
    return text;
}

std::string gzip(std::string_view bytes, const fs::path& scratch) {
    const fs::path file = scratch / "seed.gz";
    gzFile out = gzopen(file.c_str(), "wb9");
    gzwrite(out, bytes.data(), unsigned(bytes.size()));
    gzclose(out);
    return read_file(file);
}

void ply_seeds(const fs::path& scenes, SeedWriter& seeds, const fs::path& scratch) {
    const fs::path bunny = scenes / "stanford" / "bunny_res2.ply";
    if (!fs::exists(bunny)) return;
    const prism::Mesh patch = patch_of(prism::load_ply(bunny), 48);
    const char* names[] = {"ascii", "le", "be"};
    for (PlyFormat format : {PlyFormat::Ascii, PlyFormat::Little, PlyFormat::Big})
        for (bool extras : {false, true})
            seeds.add("ply", std::string("bunny-patch-") + names[int(format)] + (extras ? "-extras" : "") + ".ply",
                      write_ply(patch, format, extras));
    seeds.add("ply", "bunny-patch-ascii.ply.gz", gzip(write_ply(patch, PlyFormat::Ascii, false), scratch));
    seeds.add("ply", "bunny-patch-meshlab-textured-ascii.ply", write_meshlab_ply(patch, PlyFormat::Ascii));
    seeds.add("ply", "bunny-patch-meshlab-textured-le.ply", write_meshlab_ply(patch, PlyFormat::Little));
    // The real header, cut after a few body lines: the truncation paths.
    const std::string real = read_file(bunny);
    seeds.add("ply", "bunny-truncated.ply", real.substr(0, std::min<size_t>(real.size(), 2048)));
}

// ---- OBJ + MTL ---------------------------------------------------------------------------------------------------

std::string rewrite_lines(const std::string& text, const std::string& keyword, const std::string& replacement) {
    std::istringstream in(text);
    std::string out;
    for (std::string line; std::getline(in, line);) {
        size_t start = line.find_first_not_of(" \t");
        if (start != std::string::npos && line.compare(start, keyword.size(), keyword) == 0 &&
            line.size() > start + keyword.size() &&
            std::isspace(static_cast<unsigned char>(line[start + keyword.size()])))
            line = line.substr(0, start) + keyword + " " + replacement;
        out += line + "\n";
    }
    return out;
}

std::string mtl_with_fixture_textures(std::string mtl) {
    for (const char* map : {"map_Kd", "map_Ka", "map_Ks", "map_d", "map_bump", "bump", "map_Ns", "disp"})
        mtl = rewrite_lines(mtl, map, "tex.png");
    return mtl;
}

void obj_seeds(const fs::path& scenes, SeedWriter& seeds) {
    for (const fs::path& obj : files_with(scenes, {".obj"})) {
        if (fs::file_size(obj) > kMaxSeedBytes) continue;
        std::string text = read_file(obj);
        std::string mtl_name;
        std::istringstream lines(text);
        for (std::string line; std::getline(lines, line);)
            if (line.rfind("mtllib ", 0) == 0) mtl_name = line.substr(7);
        while (!mtl_name.empty() && std::isspace(static_cast<unsigned char>(mtl_name.back()))) mtl_name.pop_back();
        std::string seed = rewrite_lines(text, "mtllib", "fuzz.mtl");
        fs::path mtl = prism::find_file_case_insensitive(obj.parent_path(), mtl_name);
        if (!mtl.empty()) seed += "#prism-fuzz-mtl\n" + mtl_with_fixture_textures(read_file(mtl));
        seeds.add("obj", obj.stem().string() + ".txt", seed);
    }
    // Every real MTL on a textured triangle that uses its first material: the MTL statements real files contain.
    for (const fs::path& mtl : files_with(scenes, {".mtl"})) {
        const std::string text = read_file(mtl);
        std::istringstream lines(text);
        std::string first;
        for (std::string line; std::getline(lines, line) && first.empty();)
            if (line.rfind("newmtl ", 0) == 0) first = line.substr(7);
        std::string seed =
            "mtllib fuzz.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
            "g patch\nusemtl " +
            first +
            "\nf 1/1/1 2/2/1 3/3/1\nf 2/2 4/3 3/1\nf -1//1 -2//1 -3//1\n"
            "#prism-fuzz-mtl\n" +
            mtl_with_fixture_textures(text);
        seeds.add("obj", "mtl-" + mtl.parent_path().filename().string() + "-" + mtl.stem().string() + ".txt", seed);
    }
}

// ---- glTF and GLB ------------------------------------------------------------------------------------------------

std::string base64(std::string_view bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= uint8_t(bytes[i + 2]);
        out += digits[n >> 18 & 63];
        out += digits[n >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

// A .glb of a JSON chunk and, when `bin` is not empty, a BIN chunk (buffer 0 without a uri).
std::string glb_of(const std::string& json_text, std::string bin = "") {
    std::string bin_chunk;
    if (!bin.empty()) {
        while (bin.size() % 4) bin += '\0';
        bin_chunk = prism::test::little_endian32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
    }
    return prism::join_glb("glTF" + prism::test::little_endian32(2), json_text, bin_chunk).value();
}

// Draco and meshopt files as the encoders make them from a patch of the bunny, with the compressed bytes as the
// buffer file (.gltf) or the BIN chunk (.glb), where the mutations reach them.
void compressed_gltf_seeds(const fs::path& scenes, SeedWriter& seeds) {
    const fs::path bunny = scenes / "stanford" / "bunny_res2.ply";
    if (!fs::exists(bunny)) return;
    const prism::test::PlainMesh plain = prism::test::plain_mesh(patch_of(prism::load_ply(bunny), 48));
    const std::pair<const char*, prism::test::CompressedGltf> files[] = {
        {"draco", prism::test::draco_gltf(plain)},
        {"draco-quantized", prism::test::draco_gltf(plain, 11)},
        {"meshopt", prism::test::meshopt_gltf(plain)},
        {"meshopt-octahedral", prism::test::meshopt_gltf(plain, true)}};
    for (const auto& [name, gltf] : files) {
        json with_file = gltf.document;
        with_file["buffers"][0]["uri"] = "fuzz.bin";
        seeds.add("gltf", std::string(name) + ".txt", with_file.dump() + "\n#prism-fuzz-bin\n" + gltf.buffer);
        seeds.add("glb", std::string(name) + ".glb", glb_of(gltf.document.dump(), gltf.buffer));
    }
}

// A triangle below a parent node, both animated: LINEAR translation, CUBICSPLINE rotation, STEP scale, the keys in
// an embedded buffer (the animation reader and the samplers, core/loaders/gltf_animation.h).
std::string animated_triangle_gltf() {
    prism::test::GltfBuilder gltf;
    const int positions = gltf.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int child = gltf.node({{"mesh", gltf.mesh({{{"attributes", {{"POSITION", positions}}}}})}});
    gltf.node({{"children", {child}}, {"translation", {0, 0, -2}}});
    auto floats = [&](const std::vector<float>& values, int count, const char* type) {
        return gltf.accessor(
            {{"bufferView", gltf.view(values)}, {"componentType", 5126}, {"count", count}, {"type", type}});
    };
    const int times = floats({0, 0.5f, 2}, 3, "SCALAR");
    const int moves = floats({0, 0, 0, 1, 2, 0, -1, 0, 3}, 3, "VEC3");
    const int turns = floats({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0.7f, 0, 0.7f, 0, 0, 0,
                              0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0,    0, 1,    0, 0, 0},
                             9, "VEC4");
    const int scales = floats({1, 1, 1, 2, 2, 2, 0.5f, 1, 3}, 3, "VEC3");
    gltf.document["animations"] = {{{"name", "fuzz"},
                                    {"channels",
                                     {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}},
                                      {{"sampler", 1}, {"target", {{"node", 1}, {"path", "rotation"}}}},
                                      {{"sampler", 2}, {"target", {{"node", child}, {"path", "scale"}}}}}},
                                    {"samplers",
                                     {{{"input", times}, {"output", moves}},
                                      {{"input", times}, {"output", turns}, {"interpolation", "CUBICSPLINE"}},
                                      {{"input", times}, {"output", scales}, {"interpolation", "STEP"}}}}}};
    json document = gltf.document;
    document["buffers"] = {
        {{"byteLength", gltf.buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(gltf.buffer)}}};
    document["scenes"] = {{{"nodes", {1}}}};
    return document.dump();
}

// A strip of two triangles skinned to two joints, the second turned by a LINEAR rotation channel, with a morph
// target whose weight a CUBICSPLINE weights channel keys (the deformed meshes, core/scene/mesh_deformation.h).
std::string deforming_strip_gltf() {
    prism::test::GltfBuilder gltf;
    auto floats = [&](const std::vector<float>& values, int count, const char* type) {
        return gltf.accessor(
            {{"bufferView", gltf.view(values)}, {"componentType", 5126}, {"count", count}, {"type", type}});
    };
    const int positions = gltf.positions({-0.5f, 0, 0, 0.5f, 0, 0, -0.5f, 2, 0, 0.5f, 2, 0});
    const int normals = gltf.positions({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    const int lift = gltf.positions({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0});
    const std::vector<uint8_t> joint_bytes = {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    const int joints = gltf.accessor(
        {{"bufferView", gltf.view(joint_bytes)}, {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}});
    const int weights = floats({1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0, 1, 0, 0}, 4, "VEC4");
    const int inverse_bind = floats(
        {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1}, 2, "MAT4");
    const int mesh = gltf.mesh(
        {{{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}},
          {"indices", gltf.indices({0, 1, 2, 1, 3, 2})},
          {"targets", {{{"POSITION", lift}}}}}});
    gltf.node({{"children", {1}}});                                 // 0: the root joint
    gltf.node({{"translation", {0, 1, 0}}});                        // 1: the tip joint
    gltf.node({{"mesh", mesh}, {"skin", 0}, {"weights", {0.25}}});  // 2
    gltf.document["skins"] = {{{"joints", {0, 1}}, {"inverseBindMatrices", inverse_bind}}};
    const int times = floats({0, 1, 2}, 3, "SCALAR");
    const int turns = floats({0, 0, 0, 1, 0, 0, 0.7f, 0.7f, 0, 0, -0.7f, 0.7f}, 3, "VEC4");
    const int lifts = floats({0, 0, 0, 0, 1, 2, -1, 0.5f, 0}, 9, "SCALAR");
    gltf.document["animations"] = {{{"name", "fuzz-deform"},
                                    {"channels",
                                     {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "rotation"}}}},
                                      {{"sampler", 1}, {"target", {{"node", 2}, {"path", "weights"}}}}}},
                                    {"samplers",
                                     {{{"input", times}, {"output", turns}},
                                      {{"input", times}, {"output", lifts}, {"interpolation", "CUBICSPLINE"}}}}}};
    json document = gltf.document;
    document["buffers"] = {
        {{"byteLength", gltf.buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(gltf.buffer)}}};
    document["scenes"] = {{{"nodes", {0, 2}}}};
    return document.dump();
}

void gltf_seeds(const fs::path& scenes, SeedWriter& seeds, const fs::path& scratch) {
    compressed_gltf_seeds(scenes, seeds);
    for (const fs::path& gltf : files_with(scenes, {".gltf"})) {
        json model = json::parse(read_file(gltf), nullptr, false);
        if (model.is_discarded()) continue;
        std::string bin;
        if (model.contains("buffers") && !model["buffers"].empty()) {
            const fs::path buffer = gltf.parent_path() / model["buffers"][0].value("uri", "");
            if (fs::is_regular_file(buffer) && fs::file_size(buffer) <= kMaxSeedBytes) bin = read_file(buffer);
            for (json& entry : model["buffers"]) entry["uri"] = "fuzz.bin";
        }
        if (model.contains("images"))
            for (json& image : model["images"]) image["uri"] = "tex.png";
        std::string seed = model.dump();
        if (!bin.empty()) seed += "\n#prism-fuzz-bin\n" + bin;
        seeds.add("gltf", gltf.stem().string() + ".txt", seed);
    }
    // The fixture triangle with its buffer as a data: URI (the embedded-buffer path).
    json triangle = json::parse(read_file(scratch / "tri.gltf"));
    triangle["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(read_file(scratch / "tri.bin"));
    seeds.add("gltf", "triangle-embedded.txt", triangle.dump());
    const std::string animated = animated_triangle_gltf();
    seeds.add("gltf", "animated-triangle.txt", animated);
    seeds.add("glb", "animated-triangle.glb", glb_of(animated, ""));
    const std::string deforming = deforming_strip_gltf();
    seeds.add("gltf", "deforming-strip.txt", deforming);
    seeds.add("glb", "deforming-strip.glb", glb_of(deforming, ""));
    for (const fs::path& glb : files_with(scenes, {".glb"}))
        if (fs::file_size(glb) <= kMaxSeedBytes) seeds.add("glb", glb.filename().string(), read_file(glb));
}

// ---- Prism scene files -----------------------------------------------------------------------------------------

void scene_json_seeds(const fs::path& repo, SeedWriter& seeds) {
    // The documented examples with their files swapped for the scratch folder's fixtures.
    for (const fs::path& example : files_with(repo / "docs" / "examples", {".json"})) {
        json scene = json::parse(read_file(example), nullptr, false);
        if (scene.is_discarded()) continue;
        if (scene.contains("objects"))
            for (json& object : scene["objects"]) {
                const std::string file = object.value("file", "");
                object["file"] = file.ends_with(".obj") ? "tri.obj" : file.ends_with(".ply") ? "tri.ply" : "tri.gltf";
            }
        if (scene.contains("materials"))
            for (auto& [name, material] : scene["materials"].items())
                if (material.contains("textures"))
                    for (json& layer : material["textures"]) layer["file"] = "tex.png";
        if (scene.contains("environment") && scene["environment"].contains("cubemap"))
            scene["environment"]["cubemap"] = "sky";
        seeds.add("scene_json", example.filename().string(), scene.dump(1));
    }
    seeds.add("scene_json", "equirect-obj-quaternion.json", R"({
 "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 60},
 "environment": {"equirect": "sky.hdr", "color": 0.5, "intensity": 2},
 "materials": {"dispersive": {"diffuse": 1, "transmittance": 0.5, "ior": [1.4, 1.5, 1.6], "thickness": 0.01,
   "textures": [{"file": "tex.png", "mode": "blend", "env_color": [1, 0, 0, 1], "uv_set": 0}]}},
 "objects": [{"file": "tri.obj", "material": "dispersive",
   "transform": {"translate": [1, 0, 0], "rotate": {"quaternion": [0, 0.7071, 0, 0.7071]}, "scale": [1, 2, 1]}},
   {"file": "tri.gltf", "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "name": "copy"}]})");
    seeds.add("scene_json", "constant-sky-ply.json", R"({
 "environment": {"color": [0.2, 0.3, 0.4]}, "ambient": [0.1, 0.1, 0.1],
 "lights": [{"type": "point", "position": [0, 2, 2], "color": 1, "intensity": 4},
            {"type": "directional", "direction": [0, -1, 0]}],
 "materials": {"mirror": {"reflectivity": 1, "specular": [0.9, 0.9, 0.9], "emissive": 0,
   "fresnel": {"bias": 0.1, "scale": 0.9, "power": 5}, "use_vertex_colors": false}},
 "objects": [{"file": "tri.ply", "material": "mirror", "transform": {"rotate": {"axis": [0, 1, 0], "degrees": 30}}}]})");
}

// ---- Images ------------------------------------------------------------------------------------------------------

void image_seeds(const fs::path& scenes, SeedWriter& seeds, const fs::path& scratch) {
    const std::vector<fs::path> images = files_with(scenes, {".png", ".jpg", ".jpeg", ".hdr"});
    size_t shrunk = 0;
    for (const fs::path& image : images) {
        // Small real files as they are: real encoders' choices (progressive JPEG, palettes, interlacing).
        if (fs::file_size(image) <= 8 * 1024) seeds.add("image", image.filename().string(), read_file(image));
        if (shrunk >= 6 || image.filename().string().find("reference") != std::string::npos) continue;
        // A few scaled down to at most 16x16 and re-encoded in every format stb_image_write produces.
        const bool hdr = image.extension() == ".hdr";
        int width = 0, height = 0, channels = 0;
        const std::string bytes = read_file(image);
        void* pixels =
            hdr ? static_cast<void*>(stbi_loadf_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                                            int(bytes.size()), &width, &height, &channels, 3))
                : static_cast<void*>(stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                                           int(bytes.size()), &width, &height, &channels, 4));
        if (!pixels) continue;
        const int w = std::min(width, 16), h = std::min(height, 12);
        std::vector<uint8_t> rgba(size_t(w) * h * 4);
        std::vector<float> rgb(size_t(w) * h * 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t source = size_t(y * height / h) * width + size_t(x * width / w);
                for (int c = 0; c < 3; ++c) {
                    if (hdr)
                        rgb[(size_t(y) * w + x) * 3 + c] = static_cast<float*>(pixels)[source * 3 + c];
                    else
                        rgba[(size_t(y) * w + x) * 4 + c] = static_cast<uint8_t*>(pixels)[source * 4 + c];
                }
                if (!hdr) rgba[(size_t(y) * w + x) * 4 + 3] = static_cast<uint8_t*>(pixels)[source * 4 + 3];
            }
        stbi_image_free(pixels);
        const std::string stem = image.stem().string() + "-" + std::to_string(shrunk);
        const fs::path file = scratch / "seed-image";
        if (hdr) {
            stbi_write_hdr(file.c_str(), w, h, 3, rgb.data());
            seeds.add("image", stem + ".hdr", read_file(file));
        } else {
            stbi_write_png(file.c_str(), w, h, 4, rgba.data(), w * 4);
            seeds.add("image", stem + ".png", read_file(file));
            stbi_write_png(file.c_str(), w, h, 3, rgba.data(), w * 4);  // stride 4, 3 channels: RGB data
            seeds.add("image", stem + "-rgb.png", read_file(file));
            stbi_write_jpg(file.c_str(), w, h, 4, rgba.data(), 85);
            seeds.add("image", stem + ".jpg", read_file(file));
            stbi_write_bmp(file.c_str(), w, h, 4, rgba.data());
            seeds.add("image", stem + ".bmp", read_file(file));
            stbi_write_tga(file.c_str(), w, h, 4, rgba.data());
            seeds.add("image", stem + ".tga", read_file(file));
            for (bool lossless : {true, false}) {  // WebP goes to libwebp (core/image/image_webp.h)
                uint8_t* webp = nullptr;
                const size_t size = lossless ? WebPEncodeLosslessRGBA(rgba.data(), w, h, w * 4, &webp)
                                             : WebPEncodeRGBA(rgba.data(), w, h, w * 4, 75.0f, &webp);
                seeds.add("image", stem + (lossless ? "-lossless.webp" : "-lossy.webp"),
                          std::string_view(reinterpret_cast<const char*>(webp), size));
                WebPFree(webp);
            }
        }
        ++shrunk;
    }
}

}  // namespace

// ---- Hostile cases: deep, huge counts, compressed bombs, files outside the scene (issue 17) ---------------------

std::string deep_chain_gltf(int nodes) {
    std::string text = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[)";
    for (int i = 0; i < nodes; ++i) {
        if (i) text += ',';
        text += i + 1 < nodes ? R"({"children":[)" + std::to_string(i + 1) + "]}" : R"({"mesh":0})";
    }
    text +=
        R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"buffers":[{"uri":"fuzz.bin","byteLength":36}],)"
        R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})";
    return text;
}

void hostile_seeds(SeedWriter& seeds, const fs::path& scratch) {
    const std::string tri_ply = read_file(scratch / "tri.ply");
    const std::string tri_header = tri_ply.substr(0, tri_ply.find("end_header\n") + 11);
    std::string huge_counts = tri_ply;
    huge_counts.replace(huge_counts.find("vertex 3"), 8, "vertex 4294967295");
    seeds.add("ply", "huge-vertex-count.ply", huge_counts);
    seeds.add("ply", "gzip-bomb.ply.gz", prism::test::gzip_bomb(tri_ply, ' ', size_t(1) << 20, 32));
    seeds.add("ply_header", "triangle.txt", tri_header);
    seeds.add("ply_header", "huge-counts.txt", huge_counts.substr(0, huge_counts.find("end_header\n") + 11));
    std::string many_lists =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nelement face 18446744073709551615\n";
    for (int i = 0; i < 8; ++i) many_lists += "property list uint uint extra" + std::to_string(i) + "\n";
    seeds.add("ply_header", "many-lists.txt", many_lists + "property list uchar int vertex_indices\nend_header\n");

    const std::string bin = read_file(scratch / "tri.bin").substr(0, 36);
    seeds.add("gltf", "deep-node-chain.txt", deep_chain_gltf(1500) + "\n#prism-fuzz-bin\n" + bin);
    const std::string nesting = std::string(4000, '[') + std::string(4000, ']');
    seeds.add("gltf", "deep-extras.txt", R"({"asset":{"version":"2.0"},"extras":)" + nesting + "}");
    seeds.add("glb", "deep-extras.glb", glb_of(R"({"asset":{"version":"2.0"},"extras":)" + nesting + "}"));
    json huge_accessor = json::parse(read_file(scratch / "tri.gltf"));
    huge_accessor["accessors"][2]["count"] = 2147483648u;
    huge_accessor["buffers"][0]["uri"] = "fuzz.bin";
    seeds.add("gltf", "index-count-2-to-31.txt",
              huge_accessor.dump() + "\n#prism-fuzz-bin\n" + read_file(scratch / "tri.bin"));
    json shared = json::parse(deep_chain_gltf(3));
    shared["nodes"][1]["children"] = {2};
    shared["nodes"][0]["children"] = {1, 2};
    seeds.add("gltf", "shared-child.txt", shared.dump() + "\n#prism-fuzz-bin\n" + bin);

    seeds.add("obj", "nan-vertex.txt", "v nan 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    seeds.add("obj", "huge-index.txt", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\nf 1 2 3.5e9\n");
    seeds.add("obj", "negative-index.txt", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -5 -1 -2\n");
    seeds.add("obj", "escaping-mtl.txt",
              "mtllib ../tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n#prism-fuzz-mtl\n"
              "newmtl m\nmap_Kd /etc/passwd\n");

    seeds.add("scene_json", "deep.json", R"({"lights":)" + nesting + "}");
    seeds.add("scene_json", "escaping.json", R"({"objects":[{"file":"../tri.obj"},{"file":"/etc/passwd.obj"}]})");
    seeds.add("image", "blank-2048x4096.png", prism::test::blank_png(2048, 4096));

    seeds.add("scene_refs", "fixtures.txt", "tri.obj\ntex.png\ntri.bin\ntex.png\nref.mtl\ntex.png\n");
    seeds.add("scene_refs", "mtl-texture-climbing.txt", "tri.obj\ntex.png\ntri.bin\ntex.png\nref.mtl\n../tex.png\n");
    // A texture reference in an MTL that no mtllib line names is never read (a harness false finding once).
    seeds.add("scene_refs", "unread-mtl.txt", "tri.obj\ntex.png\ntri.bin\ntex.png\ntri.mtl\n//\n");
    seeds.add("scene_refs", "climbing.txt",
              "../tri.obj\n../tex.png\n../tri.bin\n../../../../etc/passwd\n../tri.mtl\n../tex.png\n");
    seeds.add("scene_refs", "absolute.txt", "/etc/passwd\n/dev/zero\n/proc/self/status\n/etc/hostname\n/dev/null\n/\n");
    seeds.add("scene_refs", "encoded.txt",
              "./tri.ply\nscene/../tex.png\n%2e%2e/tri.bin\n%2e%2e%2ftex.png\nTRI.MTL\n.\n");
}

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: fuzz_seeds SCENES_DIR REPO_DIR OUT_DIR\n");
        return 2;
    }
    const fs::path scenes = argv[1], repo = argv[2], out = argv[3];
    if (!fs::is_directory(scenes)) {
        std::fprintf(stderr, "fuzz_seeds: %s: no such folder (the shared scenes)\n", scenes.c_str());
        return 1;
    }
    const fs::path& scratch = prism::fuzz::scratch_dir();  // the fixtures, for the seeds that copy them
    SeedWriter seeds(out);
    ply_seeds(scenes, seeds, scratch);
    obj_seeds(scenes, seeds);
    gltf_seeds(scenes, seeds, scratch);
    scene_json_seeds(repo, seeds);
    image_seeds(scenes, seeds, scratch);
    hostile_seeds(seeds, scratch);
    std::printf("fuzz seeds in %s:\n", out.c_str());
    seeds.report();
    return 0;
}
