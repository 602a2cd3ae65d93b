// The prism command as a user meets it: the main job works, bad input of every kind gives one line on stderr, an
// exit code from 1 to 127 (never a crash), and no output file; and the conventions every subcommand shares
// (docs/cli.md) and the output formats hold.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <random>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb_image.h>
#include <tinyexr.h>

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

std::string binary() { return std::getenv("PRISM_BINARY") ? std::getenv("PRISM_BINARY") : PRISM_BINARY; }

// Standard output and standard error apart (run_prism merges them).
struct SplitResult {
    int exit_code = -1;
    std::string out, err;
};
// `environment`: assignments put before the command, e.g. "PRISM_PROGRESS_DELAY=0".
SplitResult run_prism_split(const std::string& arguments, const std::string& environment = "") {
    // One file per test process: ctest runs them side by side (a shared name had one test read another's stderr).
    std::string name = "stderr-";  // appended, not "literal" + string: GCC 12 warns falsely (-Wrestrict) on that
    name += std::to_string(::getpid());
    name += ".txt";
    fs::path err = prism::test::temp_dir("cli-split") / name;
    SplitResult result;
    std::string prefix = environment.empty() ? "" : "env " + environment + " ";
    FILE* pipe = popen((prefix + "'" + binary() + "' " + arguments + " 2>'" + err.string() + "'").c_str(), "r");
    if (!pipe) return result;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
    int status = pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.err = read_bytes(err);
    fs::remove(err);
    return result;
}

size_t line_count(const std::string& text) {
    size_t lines = 0;
    for (char c : text) lines += c == '\n';
    return lines + (!text.empty() && text.back() != '\n');
}

nlohmann::json parse_json_file(const fs::path& path) {
    std::ifstream file(path);
    return nlohmann::json::parse(file, nullptr, false);
}

}  // namespace

TEST(Cli, RendersTheDefaultSceneToAPng) {
    fs::path out = prism::test::temp_dir("cli") / "default.png";
    fs::remove(out);
    prism::test::CommandResult r =
        run_prism("render --backend cpu --width 160 --height 90 --out '" + out.string() + "'");
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

// --bvh-leaf-size and --bvh-node-cost shape the SAH build (fuller leaves, fewer nodes) and are reported; values
// out of range are refused in one line naming the option.
TEST(Cli, BvhLeafSizeAndNodeCostShapeTheTree) {
    std::string info =
        "info --scene '" + prism::test::scene("stanford/bunny.ply").string() + "' --bvh-layout stack --json";
    auto scene_info = [&](const std::string& shape) {
        SplitResult r = run_prism_split(info + shape);
        EXPECT_EQ(r.exit_code, 0) << shape << ": " << r.err;
        nlohmann::json j = nlohmann::json::parse(r.out, nullptr, false);
        return j.is_object() && j.contains("scene") ? j["scene"] : nlohmann::json::object();
    };
    nlohmann::json standard = scene_info("");
    nlohmann::json fuller = scene_info(" --bvh-leaf-size 8 --bvh-node-cost 4");
    ASSERT_TRUE(standard.contains("bvh_nodes") && fuller.contains("bvh_nodes"));
    EXPECT_EQ(standard["bvh_leaf_size"], 4);
    EXPECT_EQ(standard["bvh_node_cost"], 1.0);
    EXPECT_EQ(fuller["bvh_leaf_size"], 8);
    EXPECT_EQ(fuller["bvh_node_cost"], 4.0);
    EXPECT_LT(fuller["bvh_nodes"].get<size_t>() * 3, standard["bvh_nodes"].get<size_t>() * 2);
    for (std::string bad : {"--bvh-leaf-size 0", "--bvh-leaf-size 9", "--bvh-node-cost 0", "--bvh-node-cost nan"}) {
        SplitResult r = run_prism_split(info + " " + bad);
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_EQ(line_count(r.err), 1u) << bad << ": " << r.err;
        EXPECT_NE(r.err.find(bad.substr(0, bad.find(' '))), std::string::npos) << bad << ": " << r.err;
    }
}

namespace {

// Models a user may point prism at, each refused in one line naming the file: a real model truncated, random
// bytes under each model extension, a PLY face with an index past its vertices and a PLY vertex that is NaN.
struct HostileModel {
    std::string name;
    std::function<std::string()> bytes;
};
void PrintTo(const HostileModel& model, std::ostream* os) { *os << model.name; }

std::string truncated(const std::string& model, size_t numerator, size_t denominator) {
    std::string bytes = read_bytes(prism::test::scene(model));
    return bytes.substr(0, bytes.size() * numerator / denominator);
}

const std::string kTrianglePlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

class CliHostileModel : public ::testing::TestWithParam<HostileModel> {};

}  // namespace

TEST_P(CliHostileModel, FailsCleanly) {
    fs::path file = prism::test::write_file(GetParam().name, GetParam().bytes());
    expect_clean_failure(file.string(), GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(
    Files, CliHostileModel,
    ::testing::Values(
        HostileModel{"truncated-bunny.ply", [] { return truncated("stanford/bunny.ply", 1, 2); }},
        HostileModel{"truncated-box.glb", [] { return truncated("gltf/Box/Box.glb", 2, 3); }},
        HostileModel{"random.glb", [] { return random_bytes(4096, 1); }},
        HostileModel{"random.gltf", [] { return random_bytes(4096, 2); }},
        HostileModel{"random.ply", [] { return random_bytes(4096, 3); }},
        HostileModel{"random.obj", [] { return random_bytes(4096, 4); }},
        HostileModel{"bad-index.ply", [] { return kTrianglePlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"; }},
        HostileModel{"nan-vertex.ply", [] { return kTrianglePlyHeader + "0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n"; }}),
    [](const auto& info) { return prism::test::test_name_of(info.param.name); });

TEST(Cli, MissingSceneFailsCleanly) { expect_clean_failure("/nonexistent/model.ply", "/nonexistent/model.ply"); }

TEST(Cli, UnknownBackendListsTheAvailableOnes) {
    prism::test::CommandResult r = run_prism("render --backend metal --width 8 --height 8 --out /tmp/prism-x.png");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("metal"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("cpu-ref, cpu"), std::string::npos) << r.output;
}

TEST(Cli, UnsupportedOutputFormatFailsBeforeWork) {
    prism::test::CommandResult r =
        run_prism("render --backend cpu --out '" + (prism::test::temp_dir("cli") / "image.bmp").string() + "'");
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

TEST(Cli, RaysWithoutInputOrOutputSaysWhatIsMissing) {
    prism::test::CommandResult r = run_prism("rays --scene builtin:sphere --backend cpu");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("--rays and --out are required"), std::string::npos) << r.output;
}

// `prism rays --bench` (docs/ray-queries.md): both ray sets on two backends, each hit list compared with the
// reference, throughput from the launch's time.
TEST(Cli, RaysBenchReportsPrimaryAndDiffuseRaysPerBackend) {
    fs::path json = prism::test::temp_dir("cli") / "rays-bench.json";
    prism::test::CommandResult r =
        run_prism("rays --bench --scene '" + prism::test::scene("stanford/bunny.ply").string() +
                  "' --backends cpu,cpu-ref --width 64 --height 48 --runs 2 --warmup 1 --json '" + json.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    nlohmann::json result = parse_json_file(json);
    ASSERT_TRUE(result.is_object()) << r.output;
    EXPECT_EQ(result["kind"], "ray_queries");
    ASSERT_EQ(result["backends"].size(), 2u);
    for (const nlohmann::json& backend : result["backends"]) {
        for (const char* set : {"primary", "diffuse"}) {
            SCOPED_TRACE(backend["backend"].get<std::string>() + " " + set);
            const nlohmann::json& m = backend[set];
            EXPECT_GT(m["rays"].get<size_t>(), 100u);
            EXPECT_GT(m["mrays_per_s"].get<double>(), 0.0);
            EXPECT_LE(m["min_ms"].get<double>(), m["median_ms"].get<double>());
            EXPECT_GE(m["agreement"].get<double>(), 0.999);
            // The second timing: each launch right after its rays' upload.
            EXPECT_GT(m["after_upload"]["mrays_per_s"].get<double>(), 0.0);
            EXPECT_LE(m["after_upload"]["min_ms"].get<double>(), m["after_upload"]["max_ms"].get<double>());
        }
    }
    EXPECT_EQ(result["backends"][0]["primary"]["rays"], 64 * 48);
    EXPECT_EQ(result["settings"]["ray_order"], "made");
}

// --ray-order coherent traces each set sorted (bench::coherent_order): the same rays, so the same agreement with
// the reference, which is sorted with them.
TEST(Cli, RaysBenchTracesRaysInCoherentOrder) {
    fs::path json = prism::test::temp_dir("cli") / "rays-bench-coherent.json";
    prism::test::CommandResult r =
        run_prism("rays --bench --scene '" + prism::test::scene("stanford/bunny.ply").string() +
                  "' --backends cpu --width 64 --height 48 --runs 1 --warmup 0 --ray-order coherent --json '" +
                  json.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    nlohmann::json result = parse_json_file(json);
    ASSERT_TRUE(result.is_object()) << r.output;
    EXPECT_EQ(result["settings"]["ray_order"], "coherent");
    for (const char* set : {"primary", "diffuse"}) {
        EXPECT_GT(result["backends"][0][set]["rays"].get<size_t>(), 100u) << set;
        EXPECT_GE(result["backends"][0][set]["agreement"].get<double>(), 0.999) << set;
    }
    prism::test::CommandResult bad = run_prism("rays --bench --scene builtin:bunny --ray-order sorted");
    EXPECT_NE(bad.exit_code, 0);
    EXPECT_NE(bad.output.find("--ray-order"), std::string::npos) << bad.output;
}

// --- Command-line conventions (docs/cli.md) ---

TEST(Cli, ShortAndLongOutputAliasesWriteTheImage) {
    for (const char* spelling : {"-o", "--output", "--out"}) {
        fs::path out = prism::test::temp_dir("cli") / (std::string("alias") + spelling + ".png");
        fs::remove(out);
        prism::test::CommandResult r = run_prism("render --backend cpu --width 32 --height 16 --depth 2 " +
                                                 std::string(spelling) + " '" + out.string() + "'");
        ASSERT_EQ(r.exit_code, 0) << spelling << ": " << r.output;
        EXPECT_EQ(read_bytes(out).substr(1, 3), "PNG") << spelling;
    }
}

TEST(Cli, MissingOutputNamesEverySpellingAndExits2) {
    prism::test::CommandResult r = run_prism("render --backend cpu --width 8 --height 8");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(line_count(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("-o,--out,--output is required"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("prism render --help"), std::string::npos) << r.output;
}

TEST(Cli, VersionNamesVersionCommitAndBackendsBuilt) {
    SplitResult r = run_prism_split("--version");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.rfind("prism 0.", 0), 0u) << r.out;
    EXPECT_NE(r.out.find("\ncommit "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("backends built: cpu-ref cpu"), std::string::npos) << r.out;
#ifdef PRISM_HAVE_VULKAN
    EXPECT_NE(r.out.find(" vulkan"), std::string::npos) << r.out;
#endif
#ifdef PRISM_HAVE_CUDA
    EXPECT_NE(r.out.find(" cuda"), std::string::npos) << r.out;
#endif
}

TEST(Cli, UnknownOptionExits2AndNamesIt) {
    prism::test::CommandResult r = run_prism("render --backend cpu --frobnicate 3 --out /tmp/prism-never.png");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(line_count(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("--frobnicate"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--help"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists("/tmp/prism-never.png"));
}

TEST(Cli, UnknownSubcommandExits2AndNamesIt) {
    prism::test::CommandResult r = run_prism("rendr --backend cpu");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(line_count(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("unknown subcommand 'rendr'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("render"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("prism --help"), std::string::npos) << r.output;

    prism::test::CommandResult none = run_prism("");
    EXPECT_EQ(none.exit_code, 2) << none.output;
}

TEST(Cli, JsonDashWritesOnlyJsonToStandardOutput) {
    SplitResult info = run_prism_split("info --json -");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    nlohmann::json parsed = nlohmann::json::parse(info.out, nullptr, false);
    ASSERT_FALSE(parsed.is_discarded()) << info.out;
    EXPECT_TRUE(parsed["backends"].is_array());

    SplitResult bench = run_prism_split(
        "bench --scenes builtin:sphere --backends cpu --width 24 --height 16 --depth 2 --runs 1 --warmup 0 --json -");
    ASSERT_EQ(bench.exit_code, 0) << bench.err;
    parsed = nlohmann::json::parse(bench.out, nullptr, false);
    ASSERT_FALSE(parsed.is_discarded()) << bench.out;
    EXPECT_EQ(parsed["scenes"][0]["backends"][0]["backend"], "cpu");
    EXPECT_NE(bench.err.find("builtin:sphere on cpu"), std::string::npos)
        << "the human text goes to stderr: " << bench.err;
    EXPECT_FALSE(fs::exists("-"));
}

TEST(Cli, BenchWritesFinishedRunsAndEachFailureThenFails) {
    fs::path json = prism::test::temp_dir("cli") / "bench-with-failure.json";
    fs::remove(json);
    prism::test::CommandResult r = run_prism(
        "bench --scenes builtin:sphere,/nonexistent/scene.ply --backends cpu,vulkan:no-such-device --width 24 "
        "--height 16 --depth 2 --runs 1 --warmup 0 --json '" +
        json.string() + "'");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("prism: error: bench: 2 runs failed"), std::string::npos) << r.output;
    nlohmann::json result = parse_json_file(json);
    ASSERT_FALSE(result.is_discarded()) << read_bytes(json);
    ASSERT_EQ(result["scenes"].size(), 1u);
    ASSERT_EQ(result["scenes"][0]["backends"].size(), 1u);
    EXPECT_EQ(result["scenes"][0]["backends"][0]["backend"], "cpu");
    EXPECT_GT(result["scenes"][0]["backends"][0]["frames"]["frame_ms"].get<double>(), 0.0);
    ASSERT_EQ(result["failures"].size(), 2u) << result["failures"].dump();
    EXPECT_EQ(result["failures"][0]["scene"], "builtin:sphere");
    EXPECT_EQ(result["failures"][0]["backend"], "vulkan:no-such-device");
    EXPECT_FALSE(result["failures"][0]["error"].get<std::string>().empty());
    EXPECT_EQ(result["failures"][1]["scene"], "/nonexistent/scene.ply");
    EXPECT_FALSE(result["failures"][1].contains("backend"));
    EXPECT_NE(result["failures"][1]["error"].get<std::string>().find("/nonexistent/scene.ply"), std::string::npos);
}

TEST(Cli, DataDirComesFromTheEnvironment) {
    fs::path empty = prism::test::temp_dir("cli-empty-data");
    prism::test::CommandResult missing =
        run_prism("info --scene builtin:bunny", "cd / && PRISM_DATA_DIR='" + empty.string() + "'");
    EXPECT_EQ(missing.exit_code, 1) << missing.output;
    EXPECT_NE(missing.output.find(empty.string()), std::string::npos) << missing.output;

    prism::test::CommandResult found = run_prism("info --scene builtin:bunny --json",
                                                 "cd / && PRISM_DATA_DIR='" + prism::test::scenes_dir().string() + "'");
    ASSERT_EQ(found.exit_code, 0) << found.output;
    EXPECT_NE(found.output.find("\"mesh_triangles\""), std::string::npos) << found.output;

    // --data-dir still wins over the variable.
    prism::test::CommandResult overridden =
        run_prism("info --scene builtin:bunny --data-dir '" + prism::test::scenes_dir().string() + "'",
                  "cd / && PRISM_DATA_DIR='" + empty.string() + "'");
    EXPECT_EQ(overridden.exit_code, 0) << overridden.output;
}

TEST(Cli, BuiltinScenesFindTheirDataFromAnyFolder) {
    if (std::getenv("PRISM_BINARY")) GTEST_SKIP() << "a copied binary is outside the build tree it was configured in";
    prism::test::CommandResult r = run_prism("info --scene builtin:bunny", "cd / && env -u PRISM_DATA_DIR");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("Scene builtin:bunny"), std::string::npos) << r.output;
}

// An installed prism (<prefix>/bin/prism) reads the builtin scenes' models from <prefix>/share/prism/scenes, where
// -DPRISM_INSTALL_SCENES puts them, from any folder.
TEST(Cli, InstalledPrismFindsTheScenesOfItsPrefix) {
    const char* binary = std::getenv("PRISM_BINARY") ? std::getenv("PRISM_BINARY") : PRISM_BINARY;
    fs::path prefix = prism::test::temp_dir("cli-installed-prefix");
    fs::remove_all(prefix);
    fs::create_directories(prefix / "bin");
    fs::create_directories(prefix / "share" / "prism" / "scenes");
    fs::copy_file(binary, prefix / "bin" / "prism");
    fs::create_directory_symlink(fs::absolute(prism::test::scenes_dir() / "stanford"),
                                 prefix / "share" / "prism" / "scenes" / "stanford");
    std::string command =
        "cd / && env -u PRISM_DATA_DIR '" + (prefix / "bin" / "prism").string() + "' info --scene builtin:bunny 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[4096];
    for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
    EXPECT_EQ(pclose(pipe), 0) << output;
    EXPECT_NE(output.find("Scene builtin:bunny"), std::string::npos) << output;
    fs::remove_all(prefix);
}

TEST(Cli, ProgressIsPlainLinesWithElapsedAndEtaWhenNotATerminal) {
    fs::path out = prism::test::temp_dir("cli") / "progress.png";
    // The delay at 0: these steps take milliseconds, and their every tenth is wanted here.
    SplitResult r = run_prism_split(
        "render --backend cpu --width 48 --height 32 --depth 3 --out '" + out.string() + "'", "PRISM_PROGRESS_DELAY=0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find('\r'), std::string::npos) << "no redrawn line on a pipe: " << r.err;
    EXPECT_NE(r.err.find("prism: loading builtin:sphere: done in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("prism: building the wide BVH of builtin:sphere: triangles in leaves ("), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("prism: rendering 48x32: depth 1/3 (33%), "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("elapsed, ETA "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("depth 3/3 (100%)"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("prism: "), std::string::npos) << "progress stays off stdout: " << r.out;
    EXPECT_NE(r.out.find("prism render: "), std::string::npos) << r.out;
}

// A log of a small scene holds each step's "done" line, not a screen of percentages: the tenths start once a step
// has run PRISM_PROGRESS_DELAY seconds (1 by default). A malformed delay is a one-line error naming the variable.
TEST(Cli, ShortStepsPrintOnlyTheirDoneLineWhenNotATerminal) {
    fs::path out = prism::test::temp_dir("cli") / "short-steps.png";
    SplitResult r =
        run_prism_split("render --backend cpu --width 48 --height 32 --depth 3 --out '" + out.string() + "'",
                        "PRISM_PROGRESS_DELAY=600");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("prism: loading builtin:sphere: done in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("prism: building the wide BVH of builtin:sphere: done in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("prism: rendering 48x32: done in "), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("%)"), std::string::npos) << "no tenths of a step shorter than the delay: " << r.err;
    EXPECT_EQ(r.err.find("ETA"), std::string::npos) << r.err;

    for (const char* bad : {"soon", "-1", "1e9", "2s"}) {
        SplitResult e = run_prism_split("render --backend cpu --width 8 --height 8 --out '" + out.string() + "'",
                                        std::string("PRISM_PROGRESS_DELAY=") + bad);
        EXPECT_NE(e.exit_code, 0) << bad;
        EXPECT_NE(e.err.find("PRISM_PROGRESS_DELAY='" + std::string(bad) + "' is not a number of seconds"),
                  std::string::npos)
            << e.err;
        EXPECT_EQ(line_count(e.err), 1u) << e.err;
    }
}

// Loading reports how far it has read (PLY elements, gzip input), so a large model's load has an ETA too.
TEST(Cli, LoadingAModelShowsItsFractionAndEta) {
    fs::path out = prism::test::temp_dir("cli") / "loading.png";
    const std::string dragon = prism::test::scene("stanford/dragon.ply.gz").string();
    SplitResult r = run_prism_split("render --backend cpu --scene '" + dragon +
                                        "' --width 8 --height 8 --depth 1 "
                                        "--out '" +
                                        out.string() + "'",
                                    "PRISM_PROGRESS_DELAY=0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const size_t line = r.err.find("prism: loading " + dragon + " (");
    ASSERT_NE(line, std::string::npos) << r.err;
    EXPECT_NE(r.err.find("elapsed, ETA ", line), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("prism: loading " + dragon + ": done in "), std::string::npos) << r.err;
}

TEST(Cli, QuietPrintsNothingButWritesTheImage) {
    fs::path out = prism::test::temp_dir("cli") / "quiet.png";
    fs::remove(out);
    prism::test::CommandResult r =
        run_prism("render --backend cpu --width 32 --height 16 --depth 2 --quiet --out '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output, "");
    EXPECT_TRUE(fs::exists(out));
    prism::test::CommandResult error = run_prism("--quiet render --scene /nonexistent/x.ply --out /tmp/x.png");
    EXPECT_EQ(error.exit_code, 1);
    EXPECT_EQ(line_count(error.output), 1u) << "errors still show: " << error.output;
}

// --- Output formats: the same frame as 8-bit PNG, 16-bit PNG, OpenEXR and .hdr ---

TEST(Cli, RenderWritesExrAndSixteenBitPngOfTheSameFrame) {
    fs::path dir = prism::test::temp_dir("cli-formats");
    std::string common = "render --backend cpu --width 40 --height 24 --depth 3 ";
    ASSERT_EQ(run_prism(common + "--out '" + (dir / "f.exr").string() + "'").exit_code, 0);
    ASSERT_EQ(run_prism(common + "--png-depth 16 -o '" + (dir / "f16.png").string() + "'").exit_code, 0);
    ASSERT_EQ(run_prism(common + "-o '" + (dir / "f8.png").string() + "'").exit_code, 0);
    prism::test::CommandResult wrong = run_prism(common + "--png-depth 16 -o '" + (dir / "x.exr").string() + "'");
    EXPECT_EQ(wrong.exit_code, 1) << wrong.output;
    EXPECT_NE(wrong.output.find("--png-depth"), std::string::npos) << wrong.output;

    float* exr = nullptr;
    int width = 0, height = 0;
    const char* error = nullptr;
    ASSERT_EQ(LoadEXR(&exr, &width, &height, (dir / "f.exr").c_str(), &error), TINYEXR_SUCCESS) << (error ? error : "");
    std::unique_ptr<float, decltype(&std::free)> exr_owned(exr, &std::free);
    ASSERT_EQ(width, 40);
    ASSERT_EQ(height, 24);
    int w16 = 0, h16 = 0, c16 = 0, w8 = 0, h8 = 0, c8 = 0;
    std::unique_ptr<uint16_t, decltype(&stbi_image_free)> png16(
        stbi_load_16((dir / "f16.png").c_str(), &w16, &h16, &c16, 3), &stbi_image_free);
    std::unique_ptr<uint8_t, decltype(&stbi_image_free)> png8(stbi_load((dir / "f8.png").c_str(), &w8, &h8, &c8, 3),
                                                              &stbi_image_free);
    ASSERT_TRUE(png16 && png8);
    ASSERT_EQ(w16 * h16, width * height);
    double sum = 0.0;
    for (size_t i = 0; i < size_t(width * height) * 3; ++i) {
        float linear = exr[i / 3 * 4 + i % 3];
        float encoded = std::clamp(linear, 0.0f, 1.0f);
        encoded = encoded <= 0.0031308f ? encoded * 12.92f : 1.055f * std::pow(encoded, 1.0f / 2.4f) - 0.055f;
        // The EXR holds half floats (11 bits); the 16-bit PNG the full value, encoded.
        ASSERT_NEAR(png16.get()[i] / 65535.0f, encoded, 2e-3f) << "value " << i;
        ASSERT_NEAR(png16.get()[i] / 257.0f, png8.get()[i], 0.51f) << "value " << i;
        sum += linear;
    }
    EXPECT_GT(sum, 0.0) << "the frame is not black";
}

// --exposure and --tone-map: recorded in the stats, and out-of-range or unknown values are usage errors (exit 2,
// one line naming the option) before any work.
TEST(Cli, ExposureAndToneMapOptions) {
    fs::path dir = prism::test::temp_dir("cli-display");
    std::string common = "render --backend cpu --width 32 --height 16 --depth 2 -o '" + (dir / "d.png").string() + "' ";
    prism::test::CommandResult ok =
        run_prism(common + "--exposure -1.5 --tone-map NEUTRAL --stats '" + (dir / "d.json").string() + "'");
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    nlohmann::json stats = parse_json_file(dir / "d.json");
    EXPECT_EQ(stats["exposure"], -1.5);
    EXPECT_EQ(stats["tone_map"], "neutral");
    for (const char* bad : {"--exposure 65", "--exposure nan", "--tone-map aces", "--exposure"}) {
        SCOPED_TRACE(bad);
        prism::test::CommandResult r = run_prism(common + bad);
        EXPECT_EQ(r.exit_code, 2) << r.output;
        EXPECT_EQ(line_count(r.output), 1u) << r.output;
        EXPECT_NE(r.output.find(std::string(bad).substr(0, 10)), std::string::npos) << r.output;
    }
}

// A sky brighter than 1 seen directly: the EXR and .hdr keep it, the 8-bit PNG clips it.
TEST(Cli, ExrAndHdrKeepRadianceAboveOne) {
    prism::test::write_file(
        "bright-triangle.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    fs::path scene = prism::test::write_file(
        "bright-sky.json",
        R"({"camera": {"position": [0.3, 0.3, 3.0], "target": [0.3, 0.3, 0.0], "up": [0, 1, 0], "fov": 45},
            "environment": {"color": [6.0, 3.0, 0.5]},
            "objects": [{"name": "triangle", "file": "bright-triangle.ply"}]})");
    fs::path dir = prism::test::temp_dir("cli-bright");
    for (const char* name : {"sky.exr", "sky.hdr", "sky.png"}) {
        prism::test::CommandResult r =
            run_prism("render --scene '" + scene.string() + "' --backend cpu --width 16 --height 16 --depth 2 -o '" +
                      (dir / name).string() + "'");
        ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    }
    float* exr = nullptr;
    int width = 0, height = 0;
    const char* error = nullptr;
    ASSERT_EQ(LoadEXR(&exr, &width, &height, (dir / "sky.exr").c_str(), &error), TINYEXR_SUCCESS)
        << (error ? error : "");
    std::unique_ptr<float, decltype(&std::free)> exr_owned(exr, &std::free);
    // The top-left pixel sees only the sky.
    EXPECT_FLOAT_EQ(exr[0], 6.0f);
    EXPECT_FLOAT_EQ(exr[1], 3.0f);
    EXPECT_FLOAT_EQ(exr[2], 0.5f);

    int channels = 0;
    std::unique_ptr<float, decltype(&stbi_image_free)> hdr(
        stbi_loadf((dir / "sky.hdr").c_str(), &width, &height, &channels, 3), &stbi_image_free);
    ASSERT_TRUE(hdr);
    EXPECT_NEAR(hdr.get()[0], 6.0f, 6.0f / 128.0f);  // RGBE: 8 bits of mantissa shared
    EXPECT_NEAR(hdr.get()[1], 3.0f, 6.0f / 128.0f);

    std::unique_ptr<uint8_t, decltype(&stbi_image_free)> png(
        stbi_load((dir / "sky.png").c_str(), &width, &height, &channels, 3), &stbi_image_free);
    ASSERT_TRUE(png);
    EXPECT_EQ(png.get()[0], 255);
    EXPECT_EQ(png.get()[1], 255);
    EXPECT_NEAR(png.get()[2], 188, 1);  // sRGB of 0.5
}
