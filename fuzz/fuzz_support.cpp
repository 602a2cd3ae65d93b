#include "fuzz/fuzz_support.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/render/device_scene.h"
#include "core/scene/scene_motion.h"
#include "core/image/image_io.h"
#include "core/loaders/scene_loader.h"

namespace prism::fuzz {
namespace {

// A triangle with UVs and a textured material, in each model format a scene file can place. Small on purpose:
// they are loaded on every scene-file input that names them.
constexpr std::string_view kTriPly =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
constexpr std::string_view kTriObj =
    "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl textured\n"
    "f 1/1/1 2/2/1 3/3/1\n";
constexpr std::string_view kTriMtl = "newmtl textured\nKd 0.8 0.8 0.8\nmap_Kd tex.png\n";
constexpr std::string_view kTriGltf = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0}],
"images":[{"uri":"tex.png"}],"buffers":[{"uri":"tri.bin","byteLength":66}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24},
{"buffer":0,"byteOffset":60,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"},
{"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}]})";

std::string tri_bin() {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float uvs[6] = {0, 0, 1, 0, 0, 1};
    const uint16_t indices[3] = {0, 1, 2};
    std::string bytes(reinterpret_cast<const char*>(positions), sizeof positions);
    bytes.append(reinterpret_cast<const char*>(uvs), sizeof uvs);
    bytes.append(reinterpret_cast<const char*>(indices), sizeof indices);
    return bytes;
}

void write_fixtures(const std::filesystem::path& dir) {
    std::vector<uint32_t> texels(16);
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = 0xff000000u | uint32_t(i * 0x0f0f0f);
    write_png(dir / "tex.png", 4, 4, texels);
    write_file(dir / "tri.ply", kTriPly);
    write_file(dir / "tri.obj", kTriObj);
    write_file(dir / "tri.mtl", kTriMtl);
    write_file(dir / "tri.gltf", kTriGltf);
    write_file(dir / "tri.bin", tri_bin());
    std::filesystem::create_directory(dir / "sky");
    for (const char* face : {"right", "left", "up", "down", "front", "back"})
        write_png(dir / "sky" / (std::string(face) + ".png"), 2, 2, std::span(texels).first(4));
    std::vector<float> sky(4 * 2 * 4, 0.5f);
    write_hdr(dir / "sky.hdr", 4, 2, sky);
}

std::filesystem::path make_scratch_dir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/prism-fuzz-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
        std::perror("prism fuzz: mkdtemp");
        std::abort();
    }
    std::filesystem::path dir = std::filesystem::absolute(pattern);
    write_fixtures(dir);
    return dir;
}

void remove_scratch_dir() {
    std::error_code ignored;
    std::filesystem::remove_all(scratch_dir(), ignored);
}

}  // namespace

const std::filesystem::path& scratch_dir() {
    static const std::filesystem::path dir = [] {
        std::filesystem::path made = make_scratch_dir();
        std::atexit(remove_scratch_dir);
        return made;
    }();
    return dir;
}

void write_file(const std::filesystem::path& path, std::string_view bytes) {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!file) {
        std::fprintf(stderr, "prism fuzz: cannot write %s\n", path.c_str());
        std::abort();  // the harness's own failure, not the loader's: stop rather than fuzz nothing
    }
}

TwoFiles split_two_files(std::string_view input, std::string_view separator) {
    const std::string line = "\n" + std::string(separator) + "\n";
    const size_t at = input.find(line);
    if (at == std::string_view::npos) return {input, {}, false};
    return {input.substr(0, at), input.substr(at + line.size()), true};
}

void load_two_files(const uint8_t* data, size_t size, std::string_view separator, const std::string& main,
                    const std::string& companion) {
    const std::filesystem::path& dir = scratch_dir();
    const TwoFiles files = split_two_files(as_text(data, size), separator);
    write_file(dir / main, files.first);
    std::error_code ignored;
    if (files.found)
        write_file(dir / companion, files.second);
    else
        std::filesystem::remove(dir / companion, ignored);
    load_and_build(dir / main);
}

void load_and_build_or_throw(const std::filesystem::path& scene_file) {
    LoadOptions options;
    options.data_dir = scratch_dir() / "no-data";  // bare models get the constant sky, not a cube map from disk
    const Scene scene = load_scene(scene_file.string(), options);
    (void)build_device_scene(scene);
    // An animation's samplers at its start, inside it and past its end (looped), as a sequence would take them.
    if (scene.animation.plays())
        for (double seconds : {0.0, scene.animation.duration / 3.0, scene.animation.duration * 2.5}) {
            (void)instance_transforms_at(scene, seconds);
            (void)deformed_meshes_at(scene.animation, seconds);
        }
}

void load_and_build(const std::filesystem::path& scene_file) {
    expect_clean_outcome([&] { load_and_build_or_throw(scene_file); });
}

void check_error_message(const char* message) {
    // PRISM_FUZZ_SHOW_ERRORS=1 prints every rejection: to see whether seeds load or which check stops them.
    static const bool show = std::getenv("PRISM_FUZZ_SHOW_ERRORS") != nullptr;
    if (show) std::fprintf(stderr, "rejected: %s\n", message);
    const std::string_view text(message);
    const char* broken = nullptr;
    if (text.empty())
        broken = "empty error message";
    else if (text.find_first_of("\r\n") != std::string_view::npos)
        broken = "error message spans several lines";
    else if (text.front() != '/' || text.find(": ") == std::string_view::npos)
        broken = "error message does not name the file (\"<file>: <cause>\")";
    else if (text.substr(text.find(": ") + 2).find_first_not_of(' ') == std::string_view::npos)
        broken = "error message gives no cause";  // "<file>: " (a cause may itself end in ':', "not found : a.b:")
    if (!broken) return;
    std::fprintf(stderr, "prism fuzz: %s: \"%s\"\n", broken, message);
    std::abort();
}

void report_escaped_exception(const char* type, const char* message) {
    std::fprintf(stderr, "prism fuzz: a loader let a %s escape instead of prism::Error: \"%s\"\n", type, message);
    std::abort();
}

}  // namespace prism::fuzz
