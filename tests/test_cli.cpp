// The prism command as a user meets it: the main job works, and bad input of every kind gives one line on stderr,
// an exit code from 1 to 127 (never a crash), and no output file.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using prism::test::run_prism;

std::string read_bytes(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

using prism::test::expect_clean_failure;

std::string random_bytes(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string bytes(n, '\0');
    for (char& c : bytes) c = static_cast<char>(rng() & 255u);
    return bytes;
}

}  // namespace

TEST(Cli, RendersTheDefaultSceneToAPng) {
    fs::path out = prism::test::temp_dir("cli") / "default.png";
    fs::remove(out);
    prism::test::CommandResult r = run_prism("render --backend cpu --width 160 --height 90 --out '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("on cpu"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ms"), std::string::npos) << r.output;
    std::string png = read_bytes(out);
    ASSERT_GT(png.size(), 1000u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST(Cli, InfoReportsTheDragonTriangleCount) {
    prism::test::CommandResult r =
        run_prism("info --scene '" + prism::test::scene("stanford/dragon.ply.gz").string() + "' --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("\"triangles\": 871414"), std::string::npos) << r.output.substr(0, 2000);
}

TEST(Cli, TruncatedPlyFailsCleanly) {
    std::string bunny = read_bytes(prism::test::scene("stanford/bunny.ply"));
    fs::path truncated = prism::test::write_file("truncated-bunny.ply", bunny.substr(0, bunny.size() / 2));
    expect_clean_failure(truncated.string(), "truncated-bunny.ply");
}

TEST(Cli, RandomBytesNamedAsModelsFailCleanly) {
    unsigned seed = 1;
    for (const char* name : {"random.glb", "random.gltf", "random.ply", "random.obj"}) {
        fs::path file = prism::test::write_file(name, random_bytes(4096, seed++));
        expect_clean_failure(file.string(), name);
    }
}

TEST(Cli, TruncatedGlbFailsCleanly) {
    std::string glb = read_bytes(prism::test::scene("gltf/Box/Box.glb"));
    fs::path file = prism::test::write_file("truncated-box.glb", glb.substr(0, glb.size() * 2 / 3));
    expect_clean_failure(file.string(), "truncated-box.glb");
}

TEST(Cli, OutOfRangeIndexFailsCleanly) {
    fs::path file = prism::test::write_file(
        "bad-index.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    expect_clean_failure(file.string(), "bad-index.ply");
}

TEST(Cli, NanVertexFailsCleanly) {
    fs::path file = prism::test::write_file(
        "nan-vertex.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n");
    expect_clean_failure(file.string(), "nan-vertex.ply");
}

TEST(Cli, MissingSceneFailsCleanly) { expect_clean_failure("/nonexistent/model.ply", "/nonexistent/model.ply"); }

TEST(Cli, UnknownBackendListsTheAvailableOnes) {
    prism::test::CommandResult r = run_prism("render --backend metal --width 8 --height 8 --out /tmp/prism-x.png");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("metal"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("cpu-ref, cpu"), std::string::npos) << r.output;
}

TEST(Cli, UnsupportedOutputFormatFailsBeforeWork) {
    prism::test::CommandResult r = run_prism("render --backend cpu --out '" +
                                             (prism::test::temp_dir("cli") / "image.bmp").string() + "'");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("image.bmp"), std::string::npos) << r.output;
}

TEST(Cli, RaysFileOfWrongSizeFailsCleanly) {
    fs::path rays = prism::test::write_file("odd.bin", std::string(33, '\0'));
    fs::path out = prism::test::temp_dir("cli") / "odd-hits.bin";
    prism::test::CommandResult r = run_prism("rays --scene builtin:sphere --backend cpu --rays '" + rays.string() +
                                             "' --out '" + out.string() + "'");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("odd.bin"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}
