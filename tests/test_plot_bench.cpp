// bench/plot_bench.py, the one program that draws Prism's charts, on the result files committed in bench/results:
// every kind of result (seed table and ray throughput from `prism bench`, the sweep from `prism bandwidth`) gives a
// PNG, and a file it cannot draw gives a one-line error naming it and no PNG; and the scaling chart of split renders
// from `prism render --stats` files of the layout prism writes. Skipped, saying so, where no Python 3 with matplotlib
// is installed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <stb_image.h>

#include "bench/plot_script.h"
#include "core/util/error.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

fs::path committed(const std::string& relative) { return fs::path(PRISM_SOURCE_DIR) / "bench/results" / relative; }

#define SKIP_WITHOUT_MATPLOTLIB()            \
    if (prism::bench::plot_python().empty()) \
    GTEST_SKIP() << "no Python 3 with matplotlib (Debian: python3-matplotlib): plot_bench.py not run"

void expect_png(const fs::path& path) {
    int width = 0, height = 0, channels = 0;
    ASSERT_TRUE(stbi_info(path.c_str(), &width, &height, &channels)) << path << ": not an image";
    EXPECT_GT(width, 800) << path;
    EXPECT_GT(height, 400) << path;
    std::ifstream in(path, std::ios::binary);
    char signature[8] = {};
    in.read(signature, 8);
    EXPECT_EQ(std::string(signature + 1, 3), "PNG") << path;
}

TEST(PlotBench, DrawsEveryKindOfCommittedResult) {
    SKIP_WITHOUT_MATPLOTLIB();
    fs::path dir = prism::test::temp_dir("plot-bench");
    // The seed table at both settings; then a chart of mixed rows: the cpu backend's table and the bandwidth sweep.
    const std::vector<std::pair<std::string, std::vector<fs::path>>> charts = {
        {"seed-table.png", {committed("h100/seed-table-1080p.json"), committed("h100/seed-table-seed-setting.json")}},
        {"mixed.png", {committed("cpu2/cpu-vs-embree.json"), committed("h100/bandwidth.json")}},
    };
    for (const auto& [name, results] : charts) {
        fs::path out = dir / name;
        fs::remove(out);
        EXPECT_NO_THROW(prism::bench::run_plot_script(results, out, "test")) << name;
        expect_png(out);
    }
}

TEST(PlotBench, AFileItCannotDrawIsNamedAndNothingIsWritten) {
    SKIP_WITHOUT_MATPLOTLIB();
    fs::path out = prism::test::temp_dir("plot-bench") / "not-drawn.png";
    fs::remove(out);
    fs::path viewer_log = committed("h100/view-sphere-1080p.json");
    std::string message = prism::test::error_message([&] { prism::bench::run_plot_script({viewer_log}, out, "test"); });
    EXPECT_NE(message.find(viewer_log.string()), std::string::npos) << message;
    EXPECT_NE(message.find("not a `prism bench`"), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));

    fs::path broken = prism::test::write_file("broken-result.json", "{\"kind\": \"frames\", \"scenes\": [");
    message = prism::test::error_message([&] { prism::bench::run_plot_script({broken}, out, "test"); });
    EXPECT_NE(message.find("invalid JSON"), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));
}

// `prism render --stats` as prism writes it (fields of a real run, small values): a one-device render has no
// "workers"; a split one has "ranks", "workers" and "tile_size"/"tiles" (a frame) or "frames"/"sequence_ms".
std::string render_stats(double frame_ms, const std::string& backend, const std::string& split = "") {
    return R"({"api_version": "", "backend": ")" + backend + R"(", "bvh": {"layout": "stack", "method": "sah"},
      "commit": "0123456789ab", "device": "test", "driver": "", "frame_ms": )" +
           std::to_string(frame_ms) + R"(,
      "height": 180, "host_ms": {"device_wait": 0.0, "enqueue": 0.0, "readback": 0.0}, "max_depth": 8,
      "mrays_per_second": 3.4, "queue_capacity": 0, "queue_regrows": 0, "rays_per_depth": [57600, 40000],
      "scene": "builtin:sphere", "shadow_rays_per_depth": [50000, 30000], "stage_ms": {}, "stages": [],
      "total_rays": 463550, "width": 320)" +
           split + "}";
}

std::string worker(int rank, int index, const std::string& backend, const std::string& device, const char* item,
                   int items, double ms) {
    return R"({"backend": ")" + backend + R"(", "device": ")" + device + R"(", "rank": )" + std::to_string(rank) +
           R"(, "render_ms": )" + std::to_string(ms) + R"(, ")" + item + R"(": )" + std::to_string(items) +
           R"(, "worker": )" + std::to_string(index) + "}";
}

// A frame split into tiles, and a sequence split by frames, over the given workers (worker() rows).
std::string tiled_stats(double frame_ms, const std::string& backend, double wall_ms, const std::string& workers) {
    return render_stats(frame_ms, backend,
                        R"(, "ranks": 1, "tile_size": 64, "tiles": 15, "wall_ms": )" + std::to_string(wall_ms) +
                            R"(, "workers": [)" + workers + "]");
}
std::string sequence_stats(double sequence_ms, const std::string& backend, double wall_ms, const std::string& workers) {
    return render_stats(
        sequence_ms, backend,
        R"(, "frames": {"first": 0, "last": 11, "pattern": "t/f%04d.png"}, "ranks": 1, "sequence_ms": )" +
            std::to_string(sequence_ms) + R"(, "wall_ms": )" + std::to_string(wall_ms) + R"(, "workers": [)" + workers +
            "]");
}

TEST(PlotBench, DrawsTheScalingOfSplitRenders) {
    SKIP_WITHOUT_MATPLOTLIB();
    const std::string gpu = "NVIDIA H100 80GB HBM3", host = "AMD EPYC (16 threads, avx2)";
    fs::path frame = prism::test::write_file("scale-cuda.json", render_stats(80.0, "cuda"));
    fs::path sequence =
        prism::test::write_file("scale-turntable-cuda.json",
                                sequence_stats(960.0, "cuda", 1100.0, worker(0, 0, "cuda", gpu, "frames", 12, 959.0)));
    fs::path cuda_cpu = prism::test::write_file(
        "scale-cuda-cpu.json",
        tiled_stats(72.0, "cuda,cpu", 90.0,
                    worker(0, 0, "cuda", gpu, "tiles", 13, 70.0) + ", " + worker(0, 1, "cpu", host, "tiles", 2, 71.0)));
    fs::path all = prism::test::write_file("scale-cuda-all.json",
                                           tiled_stats(42.0, "cuda:all", 60.0,
                                                       worker(0, 0, "cuda:0", gpu, "tiles", 8, 41.0) + ", " +
                                                           worker(0, 1, "cuda:1", gpu, "tiles", 7, 40.0)));
    fs::path turntable = prism::test::write_file("scale-turntable-cuda-cpu.json",
                                                 sequence_stats(900.0, "cuda,cpu", 1000.0,
                                                                worker(0, 0, "cuda", gpu, "frames", 11, 880.0) + ", " +
                                                                    worker(0, 1, "cpu", host, "frames", 1, 890.0)));
    fs::path out = prism::test::temp_dir("plot-bench") / "scale.png";
    fs::remove(out);
    EXPECT_NO_THROW(prism::bench::run_plot_script({cuda_cpu, all, turntable}, out, "test", {frame, sequence}));
    expect_png(out);

    // A split render of another kind than any --baseline, and a worker without its backend: one line, no PNG.
    fs::remove(out);
    std::string message =
        prism::test::error_message([&] { prism::bench::run_plot_script({turntable}, out, "test", {frame}); });
    EXPECT_NE(message.find(turntable.string()), std::string::npos) << message;
    EXPECT_NE(message.find("--baseline"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));
    fs::path malformed = prism::test::write_file(
        "scale-malformed.json",
        render_stats(72.0, "cuda,cpu", R"(, "ranks": 1, "tile_size": 64, "tiles": 15, "workers": [{"rank": 0}])"));
    message = prism::test::error_message([&] { prism::bench::run_plot_script({malformed}, out, "test", {frame}); });
    EXPECT_NE(message.find(malformed.string()), std::string::npos) << message;
    EXPECT_NE(message.find("missing backend"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace
