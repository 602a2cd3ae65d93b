// OBJ/MTL loading: the McGuire archive scenes, the MTL-to-seed material mapping, and malformed input.
#include "core/loaders/load_obj.h"

#include <fstream>
#include <functional>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "core/image/image_io.h"
#include "tests/test_support.h"

namespace prism {
namespace {

using test::error_message;

Scene load(const std::filesystem::path& path) {
    Scene scene;
    load_obj(path, scene);
    return scene;
}

void expect_consistent(const Scene& scene) {
    ASSERT_EQ(scene.meshes.size(), 1u);
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].mesh, 0u);
    EXPECT_EQ(scene.instances[0].transform, glm::mat4(1.0f));
    const Mesh& mesh = scene.meshes[0];
    ASSERT_EQ(mesh.triangle_materials.size(), mesh.triangles.size());
    for (uint32_t material : mesh.triangle_materials) ASSERT_LT(material, scene.materials.size());
    for (const glm::uvec3& t : mesh.triangles)
        ASSERT_TRUE(t.x < mesh.positions.size() && t.y < mesh.positions.size() && t.z < mesh.positions.size());
    EXPECT_TRUE(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size());
    EXPECT_TRUE(mesh.uv0.empty() || mesh.uv0.size() == mesh.positions.size());
    for (const Material& material : scene.materials)
        for (const TextureLayer& layer : material.textures) ASSERT_LT(layer.texture, scene.textures.size());
}

TEST(LoadObj, ConferenceRoom) {
    Scene scene = load(test::scene("mcguire/conference/conference.obj"));
    expect_consistent(scene);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 331179u);
    EXPECT_TRUE(scene.textures.empty());
    EXPECT_GT(scene.materials.size(), 10u);
}

TEST(LoadObj, SibenikWithTextures) {
    Scene scene = load(test::scene("mcguire/sibenik/sibenik.obj"));
    expect_consistent(scene);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 75284u);
    EXPECT_FALSE(scene.textures.empty());
    EXPECT_FALSE(scene.meshes[0].uv0.empty());
}

TEST(LoadObj, SponzaTexturesResolveCaseInsensitively) {
    const std::filesystem::path obj = test::scene("mcguire/dabrovic-sponza/sponza.obj");
    Scene scene = load(obj);
    expect_consistent(scene);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 66450u);
    // Every map_Kd in the MTL became a texture layer on its material, and the files loaded.
    std::ifstream mtl(obj.parent_path() / "sponza.mtl");
    size_t map_kd_lines = 0;
    for (std::string line; std::getline(mtl, line);)
        if (line.find("map_Kd") != std::string::npos) ++map_kd_lines;
    size_t layers = 0;
    for (const Material& material : scene.materials) layers += material.textures.size();
    EXPECT_EQ(layers, map_kd_lines);
    EXPECT_GT(map_kd_lines, 10u);
    for (const Texture& texture : scene.textures) {
        EXPECT_GT(texture.width, 0) << texture.name;
        EXPECT_EQ(texture.encoding, TextureEncoding::Srgb8);
    }
    // sponza.mtl names "SP_LUK.JPG"; the file on disk is "sp_luk.JPG".
    bool found_sp_luk = false;
    for (const Texture& texture : scene.textures)
        found_sp_luk |= std::filesystem::path(texture.name).filename() == "sp_luk.JPG";
    EXPECT_TRUE(found_sp_luk);
}

std::filesystem::path write_in(const std::filesystem::path& directory, const std::string& name,
                               const std::string& text) {
    std::filesystem::create_directories((directory / name).parent_path());
    std::ofstream(directory / name, std::ios::binary) << text;
    return directory / name;
}

const char* kMaterials = R"(
newmtl glass
Kd 0.1 0.2 0.3
Ks 1 1 1
Ni 1.5
d 0.25
Tf 0.9 0.8 0.7
illum 7

newmtl mirror
Kd 0 0 0
Ks 0.5 0.9 0.7
illum 3

newmtl diamond_mirror
Ks 0.4 0.4 0.4
Ni 2.5
illum 5

newmtl lamp
Kd 1 1 1
Ke 10 9 8
Tr 0.5

newmtl textured
Kd 1 1 1
map_Kd -s 2 2 1 maps\Wood.PNG
)";

TEST(LoadObj, MaterialMappingAndCorners) {
    const std::filesystem::path directory = test::temp_dir("obj_mapping");
    write_in(directory, "scene.mtl", kMaterials);
    write_in(directory, "Maps/wood.png", "");
    write_png(directory / "Maps" / "wood.png", 2, 1, std::vector<uint32_t>{0xff0000ffu, 0xff00ff00u});
    const std::filesystem::path obj = write_in(directory, "scene.obj", R"(mtllib scene.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1
usemtl glass
f 1/1/1 2/2/1 3/3/1 4/4/1
usemtl mirror
f 1/2/1 2/2/1 3/2/1
usemtl diamond_mirror
f -4/1/1 -3/1/1 -2/1/1
usemtl lamp
f 1/1/1 3/3/1 4/4/1
usemtl textured
f 1/1/1 2/2/1 3/3/1 4/4/1
)");
    Scene scene = load(obj);
    expect_consistent(scene);
    const Mesh& mesh = scene.meshes[0];
    ASSERT_EQ(mesh.triangles.size(), 1u + 2u + 1u + 1u + 1u + 2u);
    // Unique (v, vt, vn) corners: 1/1 2/2 3/3 4/4, then 1/2 3/2 (mirror), then 2/1 3/1 (relative indices).
    EXPECT_EQ(mesh.positions.size(), 8u);
    ASSERT_EQ(mesh.normals.size(), 8u);
    EXPECT_EQ(mesh.normals[0], glm::vec3(0, 0, 1));
    ASSERT_EQ(mesh.uv0.size(), 8u);
    EXPECT_EQ(mesh.uv0[mesh.triangles[0].z], glm::vec2(1.0f, 0.0f)) << "v is flipped: row 0 is the image top";

    ASSERT_EQ(scene.materials.size(), 6u) << "five MTL materials and the default for the first face";
    const Material& fallback = scene.materials[mesh.triangle_materials[0]];
    EXPECT_EQ(fallback.name, "default");
    const Material& glass = scene.materials[mesh.triangle_materials[1]];
    EXPECT_EQ(mesh.triangle_materials[2], mesh.triangle_materials[1]);
    EXPECT_EQ(glass.name, "glass");
    EXPECT_EQ(glass.diffuse, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(glass.transmittance, 0.75f);
    EXPECT_FLOAT_EQ(glass.reflectivity, 1.0f);
    EXPECT_EQ(glass.ambient, glm::vec3(0.9f, 0.8f, 0.7f));
    EXPECT_EQ(glass.ior, glm::vec3(1.5f));
    EXPECT_FLOAT_EQ(glass.fresnel_bias, 0.04f);
    EXPECT_FLOAT_EQ(glass.fresnel_scale, 0.96f);
    EXPECT_FLOAT_EQ(glass.fresnel_power, 5.0f);

    const Material& mirror = scene.materials[mesh.triangle_materials[3]];
    EXPECT_EQ(mirror.name, "mirror");
    EXPECT_FLOAT_EQ(mirror.reflectivity, 0.9f);
    EXPECT_EQ(mirror.specular, glm::vec3(0.5f, 0.9f, 0.7f));
    EXPECT_EQ(mirror.transmittance, 0.0f);
    EXPECT_EQ(mirror.fresnel_bias, 1.0f) << "no Ni: a plain mirror without Fresnel falloff";
    EXPECT_EQ(mirror.fresnel_scale, 0.0f);

    const Material& diamond = scene.materials[mesh.triangle_materials[4]];
    EXPECT_EQ(diamond.name, "diamond_mirror");
    EXPECT_FLOAT_EQ(diamond.reflectivity, 0.4f);
    EXPECT_NEAR(diamond.fresnel_bias, (1.5f / 3.5f) * (1.5f / 3.5f), 1e-6f);
    EXPECT_EQ(diamond.ior, glm::vec3(2.5f));

    const Material& lamp = scene.materials[mesh.triangle_materials[5]];
    EXPECT_EQ(lamp.emissive, glm::vec3(10, 9, 8));
    EXPECT_FLOAT_EQ(lamp.transmittance, 0.5f) << "Tr 0.5";
    EXPECT_EQ(lamp.ambient, glm::vec3(1.0f)) << "no Tf: white";
    EXPECT_EQ(lamp.reflectivity, 0.0f);

    const Material& textured = scene.materials[mesh.triangle_materials[6]];
    ASSERT_EQ(textured.textures.size(), 1u);
    EXPECT_EQ(textured.textures[0].mode, TextureMode::Modulate);
    EXPECT_EQ(textured.textures[0].uv_row0, glm::vec3(2.0f, 0.0f, 0.0f));
    EXPECT_EQ(textured.textures[0].uv_row1, glm::vec3(0.0f, 2.0f, -1.0f));
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].width, 2);
    EXPECT_EQ(scene.textures[0].texels[1], 0xff00ff00u);
}

// MeshLab writes "Tr 1" (fully transparent by the MTL spec) for opaque surfaces; without a "d" it is read as opaque,
// with a warning. "d 0" says what it means and stays transparent, and "Tr 0.5" half transparent (above).
TEST(LoadObj, TrOneWithoutDissolveIsReadAsOpaque) {
    const std::filesystem::path directory = test::temp_dir("obj_tr_one");
    write_in(directory, "bottle.mtl", "newmtl label\nKd 1 1 1\nTr 1.000000\nillum 2\n\nnewmtl clear\nd 0\n");
    const std::filesystem::path obj = write_in(directory, "bottle.obj",
                                               "mtllib bottle.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl label\n"
                                               "f 1 2 3\nusemtl clear\nf 1 3 2\n");
    Scene scene = load(obj);
    const Mesh& mesh = scene.meshes[0];
    const Material& label = scene.materials[mesh.triangle_materials[0]];
    const Material& clear = scene.materials[mesh.triangle_materials[1]];
    EXPECT_EQ(label.transmittance, 0.0f);
    EXPECT_EQ(label.fresnel_bias, 1.0f) << "opaque, not a dielectric";
    EXPECT_FLOAT_EQ(clear.transmittance, 1.0f);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_EQ(scene.warnings[0],
              obj.string() + ": material 'label': 'Tr 1' (fully transparent) read as opaque, as MeshLab writes it");
}

TEST(LoadObj, AppendsToAnExistingScene) {
    Scene scene;
    load_obj(test::scene("mcguire/cornell-box/CornellBox-Original.obj"), scene);
    const size_t first_materials = scene.materials.size();
    load_obj(test::scene("mcguire/cornell-box/CornellBox-Mirror.obj"), scene);
    ASSERT_EQ(scene.meshes.size(), 2u);
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.instances[1].mesh, 1u);
    for (uint32_t material : scene.meshes[1].triangle_materials) {
        EXPECT_GE(material, first_materials);
        EXPECT_LT(material, scene.materials.size());
    }
}

// ---- what other tools read and tinyobjloader does not (core/loaders/obj_text.cpp) --------------------------------

// A backslash at a line's end continues it (the OBJ format's long lines); later lines keep their numbers.
TEST(LoadObj, BackslashContinuesALineAndLaterLinesKeepTheirNumbers) {
    const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 \\\n 3 4\n";
    Scene scene = load(test::write_file("continued.obj", square));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 2u);  // the quad, fanned
    const std::filesystem::path bad = test::write_file("continued_bad.obj", square + "v nan 0 0\n");
    EXPECT_EQ(error_message([&] { load(bad); }), bad.string() + ":7: v value 'nan' is not a finite number");
}

// Corners with empty fields at their end ("1//", "1/1/"), as some exporters write them, are read as "1", "1/1".
TEST(LoadObj, CornersWithEmptyTrailingFieldsAreRead) {
    const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
    Scene plain = load(test::write_file("plain_corners.obj", vertices + "f 1 2 3\n"));
    Scene slashes = load(test::write_file("slash_corners.obj", vertices + "f 1// 2// 3//\n"));
    EXPECT_EQ(slashes.meshes[0].positions, plain.meshes[0].positions);
    EXPECT_EQ(slashes.meshes[0].triangles, plain.meshes[0].triangles);
    Scene uv = load(test::write_file("uv_corners.obj", vertices + "f 1/1/ 2/2/ 3/3/  # a comment\n"));
    ASSERT_EQ(uv.meshes[0].uv0.size(), 3u);
    EXPECT_EQ(uv.meshes[0].uv0[1], glm::vec2(1.0f, 1.0f));  // v flipped: 1 - 0
    EXPECT_TRUE(slashes.warnings.empty() && uv.warnings.empty());
}

// Texture coordinate or normal indices in a file with no vt or no vn line at all are dropped with a warning; an index
// past the ones a file does have is still an error.
TEST(LoadObj, IndicesOfAttributesTheFileLacksAreDroppedWithAWarning) {
    const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n";
    Scene scene = load(test::write_file("no_vt.obj", vertices + "f 1/1/1 2/2/1 3/3/1\n"));
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_TRUE(scene.meshes[0].uv0.empty());
    EXPECT_EQ(scene.meshes[0].normals, std::vector<glm::vec3>(3, glm::vec3(0, 0, 1)));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("no vt line"), std::string::npos) << scene.warnings[0];
    const std::filesystem::path past = test::write_file("vn_past.obj", vertices + "f 1//1 2//1 3//2\n");
    EXPECT_EQ(error_message([&] { load(past); }), past.string() + ":5: face references normal 2 but there are 1");
}

// Windows tools write a UTF-8 byte-order mark, or UTF-16: the first line's "v" was lost (every face then one vertex
// off) or the file read as no faces. Both read as the plain file, and an MTL with a mark names its material.
TEST(LoadObj, ByteOrderMarksAndUtf16ReadAsThePlainFile) {
    const std::string plain = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    auto utf16 = [](const std::string& text, bool big_endian) {
        std::string out = big_endian ? std::string("\xfe\xff", 2) : std::string("\xff\xfe", 2);
        for (char c : text) out += big_endian ? std::string{'\0', c} : std::string{c, '\0'};
        return out;
    };
    const Scene expected = load(test::write_file("plain_text.obj", plain));
    for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"bom.obj", "\xef\xbb\xbf" + plain},
                                      {"utf16le.obj", utf16(plain, false)},
                                      {"utf16be.obj", utf16(plain, true)}}) {
        SCOPED_TRACE(name);
        const Scene scene = load(test::write_file(name, bytes));
        ASSERT_EQ(scene.meshes.size(), 1u);
        EXPECT_EQ(scene.meshes[0].positions, expected.meshes[0].positions);
        EXPECT_EQ(scene.meshes[0].triangles, expected.meshes[0].triangles);
    }
    const std::filesystem::path directory = test::temp_dir("obj_bom_mtl");
    write_in(directory, "bom.mtl", "\xef\xbb\xbfnewmtl red\nKd 1 0 0\n");
    const Scene red = load(write_in(directory, "bom_mtl.obj", "mtllib bom.mtl\nusemtl red\n" + plain));
    ASSERT_EQ(red.materials.size(), 1u);
    EXPECT_EQ(red.materials[0].name, "red");
    EXPECT_TRUE(red.warnings.empty()) << red.warnings[0];
}

// ---- malformed input -----------------------------------------------------------------------------------------

TEST(LoadObjErrors, MissingTextureNamesMtlMaterialAndFile) {
    const std::filesystem::path directory = test::temp_dir("obj_missing_texture");
    const std::filesystem::path mtl = write_in(directory, "broken.mtl", "newmtl brick\nKd 1 1 1\nmap_Kd brick.png\n");
    const std::filesystem::path obj =
        write_in(directory, "broken.obj", "mtllib broken.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl brick\nf 1 2 3\n");
    EXPECT_EQ(error_message([&] { load(obj); }), mtl.string() + ": material 'brick': texture 'brick.png' not found");
}

TEST(LoadObjErrors, BadIndicesAndRandomBytes) {
    const std::filesystem::path out_of_range =
        test::write_file("out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n");
    EXPECT_EQ(error_message([&] { load(out_of_range); }),
              out_of_range.string() + ":5: face references vertex 99 but there are 3");
    const std::filesystem::path zero = test::write_file("zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    std::string message = error_message([&] { load(zero); });
    EXPECT_EQ(message, zero.string() + ":4: vertex index 0 is invalid (OBJ counts from 1)");
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;

    std::string noise;
    uint32_t state = 99;
    for (int i = 0; i < 4096; ++i) noise.push_back(static_cast<char>((state = state * 1664525u + 1013904223u) >> 24));
    const std::filesystem::path random = test::write_file("noise.obj", noise);
    message = error_message([&] { load(random); });
    EXPECT_EQ(message.rfind(random.string() + ": ", 0), 0u) << message;

    const std::filesystem::path missing = test::temp_dir("obj") / "missing.obj";
    message = error_message([&] { load(missing); });
    EXPECT_EQ(message.rfind(missing.string() + ": cannot open", 0), 0u) << message;
}

TEST(LoadObjErrors, MissingMtlIsAWarning) {
    const std::filesystem::path obj =
        test::write_file("no_mtl.obj", "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
    Scene scene = load(obj);
    ASSERT_EQ(scene.meshes[0].triangles.size(), 1u);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    ASSERT_FALSE(scene.warnings.empty());
    EXPECT_NE(scene.warnings[0].find("nowhere.mtl"), std::string::npos) << scene.warnings[0];
}

}  // namespace
}  // namespace prism
