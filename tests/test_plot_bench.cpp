// bench/plot_bench.py, the one program that draws Prism's charts, on the result files committed in bench/results:
// every kind of result (seed table and ray throughput from `prism bench`, the sweep from `prism bandwidth`) gives a
// PNG, and a file it cannot draw gives a one-line error naming it and no PNG. Skipped, saying so, where no Python 3
// with matplotlib is installed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include <stb_image.h>

#include "bench/plot_script.h"
#include "core/error.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

fs::path committed(const std::string& relative) { return fs::path(PRISM_SOURCE_DIR) / "bench/results" / relative; }

#define SKIP_WITHOUT_MATPLOTLIB()                                                                       \
    if (prism::bench::plot_python().empty())                                                           \
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

}  // namespace
