// `prism render` split over workers: several devices in one process (a --backend list), MPI ranks under mpirun,
// and sequences (--frames). The image is bit-identical to the one-process render (the PNG files are compared byte
// for byte: the same pixels encode the same way); a failing worker fails the run with one line and no image; a
// sequence writes every frame exactly once. The mpirun tests skip, saying so, when the build has no MPI.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using prism::test::CommandResult;
using prism::test::run_prism;

const std::string kFrame = " --scene builtin:sphere --width 96 --height 64 --depth 4 --tile-size 24";

std::string read_bytes(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(read_bytes(path)); }

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// OpenMPI refuses root without these; --oversubscribe lets 3 ranks share 2 cores.
std::string mpirun(int ranks) {
#ifdef PRISM_MPIEXEC
    return std::string("'") + PRISM_MPIEXEC + "' --allow-run-as-root --oversubscribe -np " + std::to_string(ranks);
#else
    (void)ranks;
    return "";
#endif
}

#ifdef PRISM_HAVE_MPI
#define REQUIRE_MPI() (void)0
#else
#define REQUIRE_MPI() GTEST_SKIP() << "this build has no MPI (libopenmpi-dev not found at configure time)"
#endif

// The one-process render of `backend`, written once per test directory.
fs::path single_render(const fs::path& dir, const std::string& backend, const std::string& extra = "") {
    fs::path out = dir / ("single-" + backend + ".png");
    CommandResult r = run_prism("render --backend " + backend + kFrame + extra + " --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
}

size_t count_lines_starting(const std::string& text, const std::string& prefix) {
    size_t count = 0, at = 0;
    while (at < text.size()) {
        size_t end = text.find('\n', at);
        if (text.compare(at, prefix.size(), prefix) == 0) ++count;
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return count;
}

uint32_t items_done(const nlohmann::json& stats, const char* what) {
    uint32_t total = 0;
    for (const auto& worker : stats.at("workers")) total += worker.at(what).get<uint32_t>();
    return total;
}

// `prism render --backend <backends>` of kFrame (under `launcher`: mpirun), writing <name>.png and <name>.json in
// `dir`; a successful run's image must equal `expected` byte for byte. Returns the --stats JSON (null on failure).
nlohmann::json split_render(const fs::path& dir, const std::string& backends, const std::string& name,
                            const fs::path& expected, const std::string& launcher = "",
                            CommandResult* command = nullptr) {
    fs::path out = dir / (name + ".png"), stats = dir / (name + ".json");
    CommandResult r = run_prism(
        "render --backend " + backends + kFrame + " --out " + quoted(out) + " --stats " + quoted(stats), launcher);
    if (command) *command = r;
    EXPECT_EQ(r.exit_code, 0) << r.output;
    if (r.exit_code != 0) return nullptr;
    EXPECT_EQ(read_bytes(out), read_bytes(expected)) << backends << " " << launcher;
    return read_json(stats);
}

TEST(SplitRender, DevicesInOneProcessMatchOneDeviceBitForBit) {
    fs::path dir = prism::test::temp_dir("split-devices");
    nlohmann::json json = split_render(dir, "cpu,cpu", "split", single_render(dir, "cpu"));
    ASSERT_FALSE(json.is_null());
    EXPECT_EQ(json.at("ranks"), 1);
    EXPECT_EQ(json.at("workers").size(), 2u);
    EXPECT_EQ(items_done(json, "tiles"), 12u);  // 96x64 in tiles of 24: 4 x 3
}

// "<api>:all": one worker per device of the API (PoCL's one CPU device here), numbered as `prism info` lists them.
TEST(SplitRender, EveryDeviceOfAnApiMatchesOneDeviceBitForBit) {
    std::string reason;
    if (!prism::test::device_present("opencl", "pocl", &reason)) GTEST_SKIP() << reason;
    fs::path dir = prism::test::temp_dir("split-all");
    CommandResult r;
    nlohmann::json json = split_render(dir, "opencl:all", "all", single_render(dir, "opencl:pocl"), "", &r);
    ASSERT_FALSE(json.is_null());
    // The devices a prism process sees, asked of one: this test process has probed the devices itself, and on the
    // H200 machine its count (two) differed from the render's (one); a GPU in exclusive-process compute mode would
    // hide from a second process like that (suspected, not confirmed).
    const fs::path listing = dir / "info.json";
    CommandResult info = run_prism("info --json " + quoted(listing));
    ASSERT_EQ(info.exit_code, 0) << info.output;
    const nlohmann::json seen = read_json(listing);
    size_t devices = 0;
    for (const nlohmann::json& backend : seen.at("backends"))
        if (backend.at("name") == "opencl") devices = backend.at("devices").size();
    ASSERT_EQ(json.at("workers").size(), devices) << json.dump(1) << "\n" << r.output;
    EXPECT_EQ(json.at("workers")[0].at("backend"), "opencl:0");
    EXPECT_EQ(items_done(json, "tiles"), 12u);
}

TEST(SplitRender, MpiRanksMatchOneProcessBitForBit) {
    REQUIRE_MPI();
    fs::path dir = prism::test::temp_dir("split-mpi");
    fs::path expected = single_render(dir, "cpu");
    for (int ranks : {2, 3}) {
        nlohmann::json json = split_render(dir, "cpu", "ranks" + std::to_string(ranks), expected, mpirun(ranks));
        ASSERT_FALSE(json.is_null());
        EXPECT_EQ(json.at("ranks"), ranks);
        ASSERT_EQ(json.at("workers").size(), size_t(ranks));
        EXPECT_EQ(items_done(json, "tiles"), 12u);
        for (const auto& worker : json.at("workers")) EXPECT_FALSE(worker.at("device").get<std::string>().empty());
    }
}

// Ranks on different APIs: cpu beside PoCL and lavapipe. On this scene the three give the same bits on one device
// (cpu with the stack layout, which a mixed list shares: worker_plan.h), so the gathered image must equal the cpu
// one byte for byte whichever rank took which tile (the queue decides that at run time; TileAgreement checks each
// API's tiles on their own).
TEST(SplitRender, MixedBackendRanksRenderTheFrame) {
    REQUIRE_MPI();
    std::string reason;
    if (!prism::test::device_present("opencl", "pocl", &reason)) GTEST_SKIP() << reason;
    if (!prism::test::device_present("vulkan", "llvmpipe", &reason)) GTEST_SKIP() << reason;
    fs::path dir = prism::test::temp_dir("split-mixed");
    nlohmann::json json = split_render(dir, "cpu,opencl:pocl,vulkan:llvmpipe", "mixed",
                                       single_render(dir, "cpu", " --bvh-layout stack"), mpirun(3));
    ASSERT_FALSE(json.is_null());
    std::set<std::string> backends;
    for (const auto& worker : json.at("workers")) backends.insert(worker.at("backend").get<std::string>());
    EXPECT_EQ(backends, (std::set<std::string>{"cpu", "opencl:pocl", "vulkan:llvmpipe"}));
    EXPECT_EQ(items_done(json, "tiles"), 12u);
}

TEST(SplitRender, AFailingRankFailsTheRunWithOneLineAndNoImage) {
    REQUIRE_MPI();
    fs::path dir = prism::test::temp_dir("split-failing");
    fs::path out = dir / "never.png";
    fs::remove(out);
    // The device filter passes the option checks and fails only when rank 1 opens its backend.
    CommandResult r = run_prism("render --backend cpu,opencl:bogus" + kFrame + " --out " + quoted(out), mpirun(2));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(count_lines_starting(r.output, "prism: error: "), 1u) << r.output;
    EXPECT_NE(r.output.find("prism: error: rank 1 (opencl:bogus): "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();

    // A bad option fails on every rank before MPI starts; only rank 0 says so.
    r = run_prism("render --backend cpu" + kFrame + " --frames 5-2 --out " + quoted(dir / "f%d.png"), mpirun(3));
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_EQ(count_lines_starting(r.output, "prism: error: "), 1u) << r.output;
    EXPECT_NE(r.output.find("--frames '5-2'"), std::string::npos) << r.output;
}

TEST(SplitRender, AFailingDeviceInOneProcessFailsTheRunWithOneLine) {
#if defined(__SANITIZE_ADDRESS__)
    // Not yet diagnosed: under AddressSanitizer this run aborts inside ASan's own deallocator ("failed to
    // deallocate") after PoCL fails to open a device in a worker thread. The main build runs the test.
    GTEST_SKIP() << "aborts in ASan's deallocator after PoCL fails in a worker thread (under investigation)";
#endif
    fs::path dir = prism::test::temp_dir("split-failing-device");
    fs::path out = dir / "never.png";
    fs::remove(out);
    CommandResult r = run_prism("render --backend cpu,opencl:bogus" + kFrame + " --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(count_lines_starting(r.output, "prism: error: "), 1u) << r.output;
    EXPECT_NE(r.output.find("prism: error: device 1 (opencl:bogus): "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // cpu has one device: an entry naming another is refused before any work, the list named.
    r = run_prism("render --backend cpu,cpu:bogus" + kFrame + " --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output, "prism: error: --backend cpu,cpu:bogus: cpu has one device, cpu:0\n");
    EXPECT_FALSE(fs::exists(out));
}

// Files named out_NN.png in `dir`, sorted.
std::vector<std::string> frame_files(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().filename().string().rfind("out_", 0) == 0) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

void expect_sequence(const fs::path& dir, const nlohmann::json& stats) {
    EXPECT_EQ(frame_files(dir),
              (std::vector<std::string>{"out_03.png", "out_04.png", "out_05.png", "out_06.png", "out_07.png"}));
    EXPECT_EQ(items_done(stats, "frames"), 5u);  // each frame rendered (and written) once
    EXPECT_NE(read_bytes(dir / "out_03.png"), read_bytes(dir / "out_04.png"));  // the camera turned
}

TEST(Sequence, OneProcessWritesEveryFrameOnceAndFrameZeroIsTheSceneCamera) {
    fs::path dir = prism::test::temp_dir("sequence-local");
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::path stats = dir / "sequence.json";
    CommandResult r = run_prism("render --backend cpu,cpu" + kFrame + " --frames 3-7 --turntable 2 --fps 4 --out " +
                                quoted(dir / "out_%02d.png") + " --stats " + quoted(stats));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_sequence(dir, read_json(stats));

    // Frame 0 of a turntable is the scene camera; frame 8 at 4 fps and 2 s a turn is a whole turn later.
    fs::path zero = dir / "zero";
    fs::create_directories(zero);
    r = run_prism("render --backend cpu" + kFrame + " --frames 0 --turntable 2 --fps 4 --out " +
                  quoted(zero / "f%d.png"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_prism("render --backend cpu" + kFrame + " --frames 8 --turntable 2 --fps 4 --out " +
                  quoted(zero / "f%d.png"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::string still = read_bytes(single_render(zero, "cpu"));
    EXPECT_EQ(read_bytes(zero / "f0.png"), still);
    EXPECT_EQ(read_bytes(zero / "f8.png"), still);
}

TEST(Sequence, MpiRanksWriteEveryFrameOnce) {
    REQUIRE_MPI();
    fs::path dir = prism::test::temp_dir("sequence-mpi");
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::path stats = dir / "sequence.json";
    CommandResult r = run_prism("render --backend cpu" + kFrame + " --frames 3-7 --turntable 2 --fps 4 --out " +
                                    quoted(dir / "out_%02d.png") + " --stats " + quoted(stats),
                                mpirun(3));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    nlohmann::json json = read_json(stats);
    EXPECT_EQ(json.at("ranks"), 3);
    expect_sequence(dir, json);
}

// A scene file's "spin": frame N shows the object at N / fps seconds; a whole turn gives frame 0's bits back.
TEST(Sequence, SpinningObjectsOfASceneFileTurnOverTheFrames) {
    fs::path dir = prism::test::temp_dir("sequence-spin");
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::path scene = dir / "spin.json";
    std::ofstream(scene) << R"({ "camera": { "position": [0, 0.2, 0.45], "target": [0, 0.08, 0] },
        "objects": [ { "file": ")"
                         << prism::test::scene("stanford/bunny_res2.ply").string() << R"(",
                       "transform": { "translate": [0.02, 0, 0] }, "spin": { "seconds": 1 } } ] })";
    for (const char* backend : {"cpu,cpu", "cpu,cpu --bvh-layout stack"}) {
        CommandResult r = run_prism("render --backend " + std::string(backend) + " --scene " + quoted(scene) +
                                    " --allow-any-path --width 64 --height 48 --depth 2 --frames 0-4 --fps 4 --out " +
                                    quoted(dir / "out_%02d.png"));
        ASSERT_EQ(r.exit_code, 0) << r.output;
        EXPECT_EQ(frame_files(dir).size(), 5u);
        std::string first = read_bytes(dir / "out_00.png");
        EXPECT_NE(read_bytes(dir / "out_01.png"), first) << backend;  // a quarter turn
        EXPECT_NE(read_bytes(dir / "out_02.png"), read_bytes(dir / "out_01.png")) << backend;
        EXPECT_EQ(read_bytes(dir / "out_04.png"), first) << backend;  // a whole turn
        // Frame 0 is the still render of the scene.
        fs::path still = dir / "still.png";
        r = run_prism("render --backend cpu --allow-any-path --scene " + quoted(scene) +
                      " --width 64 --height 48 --depth 2 --out " + quoted(still) +
                      (std::string(backend).find("stack") != std::string::npos ? " --bvh-layout stack" : ""));
        ASSERT_EQ(r.exit_code, 0) << r.output;
        EXPECT_EQ(read_bytes(still), first) << backend;
    }
    std::ofstream(dir / "bad.json") << R"({ "objects": [ { "file": ")"
                                    << prism::test::scene("stanford/bunny_res2.ply").string()
                                    << R"(", "spin": { "axis": [0, 0, 0], "seconds": 1 } } ] })";
    CommandResult r = run_prism("render --backend cpu --allow-any-path --scene " + quoted(dir / "bad.json") +
                                " --frames 0 --out " + quoted(dir / "bad_%d.png"));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("objects[0].spin.axis"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("must not be zero"), std::string::npos) << r.output;
}

// Frames are written on encoder threads while the next one renders (apps/frame_writer.h): a frame that cannot be
// written still fails the run, with one line naming its file, after the frames before it are on disk.
TEST(Sequence, AFrameThatCannotBeWrittenFailsTheRunNamingIt) {
    fs::path dir = prism::test::temp_dir("sequence-unwritable");
    fs::remove_all(dir);
    fs::create_directories(dir / "out_05.png");  // a folder where frame 5 goes
    CommandResult r =
        run_prism("render -q --backend cpu" + kFrame + " --frames 3-7 --out " + quoted(dir / "out_%02d.png"));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("out_05.png"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_TRUE(fs::exists(dir / "out_03.png"));
}

TEST(Sequence, AnOutputWithoutAFrameNumberIsRejectedBeforeWork) {
    fs::path out = prism::test::temp_dir("sequence-bad") / "still.png";
    CommandResult r = run_prism("render --backend cpu" + kFrame + " --frames 0-2 --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("frame-number field"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    r = run_prism("render --backend cpu" + kFrame + " --frames 5-2 --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("--frames '5-2'"), std::string::npos) << r.output;
}

}  // namespace
