// The files a scene names: each input line is one reference, placed where a scene can name a file — a scene
// file's object and texture, a glTF's buffer and image URI, an OBJ's mtllib and the MTL's texture — in a scene
// folder one level below the fixtures, so "../tri.obj" names a real file outside it. Besides the usual rule
// (success or one clean prism::Error), a load that succeeds while a reference resolving outside the folder names
// an existing file is a finding: Prism read what the scene may not read. Dictionary: fuzz/dict/scene_refs.dict.
#include <array>
#include <cctype>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "fuzz/fuzz_support.h"

namespace {

namespace fs = std::filesystem;

std::array<std::string, 6> references_of(std::string_view input) {
    std::array<std::string, 6> lines;
    size_t index = 0;
    while (index < lines.size() && !input.empty()) {
        const size_t end = input.find('\n');
        lines[index++] = std::string(input.substr(0, end));
        input = end == std::string_view::npos ? std::string_view() : input.substr(end + 1);
    }
    const char* defaults[] = {"tri.obj", "tex.png", "tri.bin", "tex.png", "ref.mtl", "tex.png"};
    for (size_t i = 0; i < lines.size(); ++i)
        if (lines[i].empty()) lines[i] = defaults[i];
    return lines;
}

std::string lowercase(std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

// Whether the OBJ's mtllib line (read case-insensitively) names the harness's ref.mtl; only then is the MTL's
// texture reference read at all.
bool names_ref_mtl(const fs::path& folder, const std::string& reference) {
    std::error_code error;
    const fs::path target = fs::weakly_canonical(folder / reference, error);
    const fs::path ref_mtl = fs::weakly_canonical(folder / "ref.mtl", error);
    return !error && lowercase(target.string()) == lowercase(ref_mtl.string());
}

// Whether `reference`, named from `folder`, resolves to an existing regular file outside the folder (a folder
// such as "/" cannot be read as a model or image, so naming one reads nothing).
bool names_a_file_outside(const fs::path& folder, const std::string& reference) {
    std::error_code error;
    const fs::path target = fs::weakly_canonical(folder / reference, error);
    if (error || !fs::is_regular_file(target, error)) return false;
    const fs::path root = fs::weakly_canonical(folder, error);
    const std::string inside = root.string() + "/";
    return target.string().compare(0, inside.size(), inside) != 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const fs::path folder = prism::fuzz::scratch_dir() / "scene";
    static const bool made = [&] {
        fs::create_directories(folder);
        for (const char* fixture : {"tri.obj", "tri.mtl", "tri.bin", "tex.png", "tri.ply"})
            fs::copy_file(prism::fuzz::scratch_dir() / fixture, folder / fixture, fs::copy_options::overwrite_existing);
        return true;
    }();
    (void)made;
    const auto refs = references_of(prism::fuzz::as_text(data, size));
    for (const std::string& reference : refs)
        if (reference.find('\0') != std::string::npos) return 0;  // not a path any format can hold

    nlohmann::json gltf = nlohmann::json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
      "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
      "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],"textures":[{"source":0}],
      "images":[{"uri":""}],"buffers":[{"uri":"","byteLength":66}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})");
    gltf["buffers"][0]["uri"] = refs[2];
    gltf["images"][0]["uri"] = refs[3];
    prism::fuzz::write_file(folder / "ref.gltf", gltf.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    prism::fuzz::write_file(folder / "ref.obj",
                            "mtllib " + refs[4] + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl textured\nf 1 2 3\n");
    prism::fuzz::write_file(folder / "ref.mtl", "newmtl textured\nmap_Kd " + refs[5] + "\n");
    nlohmann::json scene = {{"objects", {{{"file", refs[0]}}, {{"file", "ref.gltf"}}, {{"file", "ref.obj"}}}},
                            {"materials", {{"m", {{"textures", {{{"file", refs[1]}}}}}}}}};
    const fs::path scene_file = folder / "refs.json";
    prism::fuzz::write_file(scene_file, scene.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));

    bool loaded = false;
    prism::fuzz::expect_clean_outcome([&] {
        prism::fuzz::load_and_build_or_throw(scene_file);
        loaded = true;
    });
    if (!loaded) return 0;
    // refs[4] is read through the case-insensitive search too; the others are names the loaders resolve as given.
    // refs[5] is read only from ref.mtl, which another mtllib line leaves unread.
    const bool mtl_texture_read = names_ref_mtl(folder, refs[4]);
    for (size_t i = 0; i < refs.size(); ++i)
        if ((i != 5 || mtl_texture_read) && names_a_file_outside(folder, refs[i]))
            prism::fuzz::report_escaped_exception("read outside the scene's folder", refs[i].c_str());
    return 0;
}
