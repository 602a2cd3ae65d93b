// `prism bandwidth` end to end on the software devices CI has (PoCL for OpenCL, lavapipe for Vulkan): it runs,
// its JSON follows the schema in docs/bandwidth.md, --plot draws a PNG through bench/plot_bench.py (or says what to
// install before measuring anything), and bad options fail with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>
#include <stb_image.h>

#include "bench/plot_script.h"
#include "tests/test_support.h"
#ifdef PRISM_HAVE_VULKAN
#include "backends/vulkan/vulkan_context.h"
#endif

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// The Vulkan loader warns on stderr without a private XDG_RUNTIME_DIR; the child process inherits this one.
void set_runtime_dir() {
    fs::path dir = prism::test::temp_dir("bandwidth-xdg");
    fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace);
    setenv("XDG_RUNTIME_DIR", dir.c_str(), 1);
}

class BandwidthRun : public ::testing::Test {
protected:
    // One measured run shared by the tests below: 1 MiB, 3 repeats, JSON, and the plot where matplotlib is there.
    // ctest runs each test in a process of its own, several at once: each process writes into a folder of its own.
    static void SetUpTestSuite() {
        set_runtime_dir();
        dir_ = prism::test::temp_dir("bandwidth-run-" + std::to_string(getpid()));
        const fs::path& dir = dir_;
        json_path_ = dir / "result.json";
        plot_path_ = dir / "result.png";
        fs::remove(json_path_);
        fs::remove(plot_path_);
        can_plot_ = !prism::bench::plot_python().empty();
        std::string plot = can_plot_ ? " --plot '" + plot_path_.string() + "'" : "";
        run_ = prism::test::run_prism("bandwidth --sizes 1M --repeats 3 --json '" + json_path_.string() + "'" + plot);
        std::ifstream in(json_path_);
        if (in) result_ = json::parse(in, nullptr, false);
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }
    static inline prism::test::CommandResult run_;
    static inline fs::path dir_, json_path_, plot_path_;
    static inline json result_;
    static inline bool can_plot_ = false;
};

bool positive_finite(const json& value) {
    return value.is_number() && std::isfinite(value.get<double>()) && value.get<double>() > 0;
}

void expect_rate(const json& rate, const std::string& where, bool read_write) {
    ASSERT_TRUE(rate.is_object()) << where;
    for (const char* key : {"median_gbps", "min_gbps", "max_gbps", "median_seconds"})
        EXPECT_TRUE(positive_finite(rate[key])) << where << "." << key << " = " << rate.value(key, json()).dump();
    EXPECT_LE(rate["min_gbps"].get<double>(), rate["median_gbps"].get<double>()) << where;
    EXPECT_LE(rate["median_gbps"].get<double>(), rate["max_gbps"].get<double>()) << where;
    if (read_write) {
        ASSERT_TRUE(rate.contains("read_write_median_gbps")) << where;
        EXPECT_DOUBLE_EQ(rate["read_write_median_gbps"].get<double>(), 2 * rate["median_gbps"].get<double>()) << where;
    } else {
        EXPECT_FALSE(rate.contains("read_write_median_gbps")) << where;
    }
}

TEST_F(BandwidthRun, ExitsZeroAndMeasuresPoclAndLavapipe) {
    ASSERT_EQ(run_.exit_code, 0) << run_.output;
    ASSERT_TRUE(result_.is_object()) << "no JSON at " << json_path_;
    // Every copy kind must be there: a copy whose data check fails is dropped, so this also checks the data.
    const std::set<std::string> kinds = {"h2d/pageable", "h2d/pinned", "d2h/pageable",
                                         "d2h/pinned",   "d2d/device", "kernel_copy/device"};
    for (const char* api : {"opencl", "vulkan"}) {
        bool found = false;
        for (const json& device : result_["devices"]) {
            if (device["api"] != api || device["measurements"].empty()) continue;
            found = true;
            std::set<std::string> seen;
            for (const json& m : device["measurements"]) {
                seen.insert(m["direction"].get<std::string>() + "/" + m["memory"].get<std::string>());
                EXPECT_EQ(m["bytes"], 1u << 20);
            }
            EXPECT_EQ(seen, kinds) << api << " " << device["device"];
        }
        EXPECT_TRUE(found) << "no measured " << api << " device in\n" << run_.output;
    }
    EXPECT_NE(run_.output.find("Peak bandwidth"), std::string::npos) << run_.output;
    EXPECT_NE(run_.output.find("read+write"), std::string::npos) << "output must say how D2D bytes are counted";
}

TEST_F(BandwidthRun, JsonFollowsTheDocumentedSchema) {
    ASSERT_TRUE(result_.is_object());
    const json& r = result_;
    EXPECT_EQ(r["schema"], "prism-bandwidth/1");
    for (const char* key : {"commit", "date", "build_type", "gbps_definition"}) EXPECT_TRUE(r[key].is_string()) << key;
    EXPECT_TRUE(r["host"].is_object());
    EXPECT_EQ(r["sizes"], json::array({1u << 20}));
    EXPECT_TRUE(r["warmup"].is_number_integer());
    EXPECT_EQ(r["repeats"], 3);
    ASSERT_TRUE(r["devices"].is_array());
    ASSERT_TRUE(r["skipped_apis"].is_array());
    ASSERT_TRUE(r["summary"].is_array());
    for (const json& skipped : r["skipped_apis"]) {
        EXPECT_TRUE(skipped["api"].is_string());
        EXPECT_TRUE(skipped["reason"].is_string());
    }

    const std::set<std::string> directions = {"h2d", "d2h", "d2d", "kernel_copy"};
    const std::set<std::string> memories = {"pageable", "pinned", "device"};
    for (const json& device : r["devices"]) {
        std::string where = device.value("api", "?") + " " + device.value("device", "?");
        for (const char* key : {"api", "device", "platform", "driver", "api_version", "pci_address"})
            EXPECT_TRUE(device[key].is_string()) << where << "." << key;
        EXPECT_TRUE(device["device_memory_bytes"].is_number_unsigned()) << where;
        EXPECT_TRUE(device["memory_spec_gbps"].is_null() || positive_finite(device["memory_spec_gbps"])) << where;
        const json& link = device["link"];
        EXPECT_TRUE(link.is_null() || (link["description"].is_string() && positive_finite(link["gbps"]))) << where;
        for (const char* key : {"details", "notes"}) {
            ASSERT_TRUE(device[key].is_array()) << where << "." << key;
            for (const json& line : device[key]) EXPECT_TRUE(line.is_string()) << where << "." << key;
        }
        ASSERT_TRUE(device["measurements"].is_array()) << where;
        for (const json& m : device["measurements"]) {
            std::string direction = m.value("direction", "?");
            EXPECT_TRUE(directions.count(direction)) << where << ": " << direction;
            EXPECT_TRUE(memories.count(m.value("memory", "?"))) << where;
            EXPECT_TRUE(m["bytes"].is_number_unsigned()) << where;
            bool read_write = direction == "d2d" || direction == "kernel_copy";
            expect_rate(m["wall"], where + " " + direction + " wall", read_write);
            if (!m["device_timer"].is_null())
                expect_rate(m["device_timer"], where + " " + direction + " device_timer", read_write);
        }
    }
    for (const json& row : r["summary"]) {
        for (const char* key : {"api", "device", "direction", "memory", "timer", "spec"})
            EXPECT_TRUE(row[key].is_string()) << key;
        EXPECT_TRUE(row["bytes"].is_number_unsigned());
        EXPECT_TRUE(positive_finite(row["gbps"]));
        EXPECT_TRUE(positive_finite(row["percent_of_best_api"]));
        EXPECT_LE(row["percent_of_best_api"].get<double>(), 100.0 + 1e-9);
        EXPECT_TRUE(row["percent_of_spec"].is_null() || positive_finite(row["percent_of_spec"]));
    }
}

#ifdef PRISM_HAVE_VULKAN
// Each copy command (H2D, D2H, D2D copy) is reported per Vulkan queue: on the compute queue always, on the transfer
// queue exactly where the context finds a transfer-only family (none on lavapipe), and the report says once per
// device when there is none. CUDA and OpenCL entries keep their form, without a queue.
TEST_F(BandwidthRun, VulkanCopiesAreReportedPerQueue) {
    ASSERT_TRUE(result_.is_object());
    std::map<std::string, bool> has_transfer;  // device name -> the context found a transfer-only family
    prism::vk::Instance instance(false);
    for (const prism::vk::DeviceCandidate& d : instance.devices())
        has_transfer[d.properties.deviceName] = d.transfer_family != UINT32_MAX;
    auto key = [](const json& entry) {
        return entry["direction"].get<std::string>() + "/" + entry["memory"].get<std::string>() + "/" +
               entry.value("queue", "");
    };
    size_t without_transfer = 0;
    bool found = false;
    for (const json& device : result_["devices"]) {
        if (device["api"] != "vulkan") {
            for (const json& m : device["measurements"]) EXPECT_FALSE(m.contains("queue")) << device["api"];
            continue;
        }
        if (device["measurements"].empty()) continue;
        found = true;
        std::string name = device["device"];
        ASSERT_TRUE(has_transfer.count(name)) << name << " is not among the context's devices";
        without_transfer += !has_transfer[name];
        std::set<std::string> expected = {"kernel_copy/device/"};  // a dispatch: always the compute queue
        for (const char* queue : {"compute", "transfer"}) {
            if (std::string(queue) == "transfer" && !has_transfer[name]) continue;
            for (const char* kind : {"h2d/pageable", "h2d/pinned", "d2h/pageable", "d2h/pinned", "d2d/device"})
                expected.insert(std::string(kind) + "/" + queue);
        }
        std::set<std::string> measured, summarized;
        for (const json& m : device["measurements"]) measured.insert(key(m));
        for (const json& row : result_["summary"])
            if (row["api"] == "vulkan" && row["device"] == name) summarized.insert(key(row));
        EXPECT_EQ(measured, expected) << name;
        EXPECT_EQ(summarized, expected) << name;
    }
    ASSERT_TRUE(found) << "no measured Vulkan device in\n" << run_.output;
    EXPECT_NE(run_.output.find("D2D copy device [compute]"), std::string::npos) << run_.output;
    size_t said = 0;
    for (size_t at = run_.output.find("no transfer-only queue"); at != std::string::npos;
         at = run_.output.find("no transfer-only queue", at + 1))
        ++said;
    EXPECT_EQ(said, without_transfer) << run_.output;
}

VkQueueFamilyProperties queue_family(VkQueueFlags flags) {
    VkQueueFamilyProperties family{};
    family.queueFlags = flags;
    family.queueCount = 1;
    return family;
}

// The transfer-only family is the one that can copy but neither draw nor compute: NVIDIA's copy-engine family, never
// a compute family that also transfers. Lists as drivers report them, so the NVIDIA case runs here on lavapipe too.
TEST(Bandwidth, TransferOnlyFamilyIsNeitherGraphicsNorCompute) {
    using prism::vk::transfer_only_family;
    const VkQueueFlags g = VK_QUEUE_GRAPHICS_BIT, c = VK_QUEUE_COMPUTE_BIT, t = VK_QUEUE_TRANSFER_BIT,
                       sparse = VK_QUEUE_SPARSE_BINDING_BIT;
    std::vector<VkQueueFamilyProperties> nvidia = {queue_family(g | c | t | sparse), queue_family(t | sparse),
                                                   queue_family(c | t | sparse)};
    EXPECT_EQ(transfer_only_family(nvidia), 1u);
    std::vector<VkQueueFamilyProperties> lavapipe = {queue_family(g | c | t)};
    EXPECT_EQ(transfer_only_family(lavapipe), UINT32_MAX);
    std::vector<VkQueueFamilyProperties> compute_copies = {queue_family(g | c | t), queue_family(c | t)};
    EXPECT_EQ(transfer_only_family(compute_copies), UINT32_MAX);
}

// The context makes the transfer-only queue only when asked and when the device has that family.
TEST(Bandwidth, TransferQueueIsCreatedOnRequestWhereItExists) {
    prism::vk::DeviceCandidate device;
    device.compute_family = 2;
    device.transfer_family = 1;
    auto families = [](const std::vector<VkDeviceQueueCreateInfo>& infos) {
        std::vector<uint32_t> result;
        for (const VkDeviceQueueCreateInfo& info : infos) {
            EXPECT_EQ(info.queueCount, 1u);
            result.push_back(info.queueFamilyIndex);
        }
        return result;
    };
    EXPECT_EQ(families(prism::vk::queue_create_infos(device, true)), (std::vector<uint32_t>{2, 1}));
    EXPECT_EQ(families(prism::vk::queue_create_infos(device, false)), std::vector<uint32_t>{2});
    device.transfer_family = UINT32_MAX;
    EXPECT_EQ(families(prism::vk::queue_create_infos(device, true)), std::vector<uint32_t>{2});
}
#endif

TEST_F(BandwidthRun, PlotIsADrawnPng) {
    if (!can_plot_) GTEST_SKIP() << "no Python 3 with matplotlib here (python3-matplotlib): --plot not exercised";
    ASSERT_EQ(run_.exit_code, 0) << run_.output;
    EXPECT_NE(run_.output.find("wrote " + plot_path_.string()), std::string::npos) << run_.output;
    int width = 0, height = 0, channels = 0;
    unsigned char* pixels = stbi_load(plot_path_.c_str(), &width, &height, &channels, 3);
    ASSERT_NE(pixels, nullptr) << plot_path_ << ": " << stbi_failure_reason();
    EXPECT_GT(width, 800);
    EXPECT_GT(height, 500);
    // Not blank: axes, labels and the series leave plenty of dark pixels, and the API colours coloured ones.
    size_t dark = 0, coloured = 0;
    for (int i = 0; i < width * height; ++i) {
        unsigned char r = pixels[3 * i], g = pixels[3 * i + 1], b = pixels[3 * i + 2];
        dark += r < 64 && g < 64 && b < 64;
        coloured += std::abs(int(r) - int(g)) > 60 || std::abs(int(g) - int(b)) > 60;
    }
    stbi_image_free(pixels);
    EXPECT_GT(dark, 2000u);
    EXPECT_GT(coloured, 200u);
}

// Parses sizes without measuring anything: a filter that matches no device.
TEST(Bandwidth, AcceptsSizeLists) {
    set_runtime_dir();
    fs::path file = prism::test::temp_dir("bandwidth") / "sizes.json";
    auto run = prism::test::run_prism("bandwidth --sizes 4K,16M,256m,1G --device no-such-device --json '" +
                                      file.string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::ifstream in(file);
    json result = json::parse(in);
    EXPECT_EQ(result["sizes"], json::array({4096, 16u << 20, 256u << 20, 1u << 30}));
    EXPECT_TRUE(result["devices"].empty());
    EXPECT_NE(run.output.find("no OpenCL device matches"), std::string::npos) << run.output;
}

int line_count(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    int lines = 0;
    while (std::getline(in, line)) lines += !line.empty();
    return lines;
}

TEST(Bandwidth, BadSizesFailWithOneLine) {
    for (const char* sizes : {"12Q", "abc", "1000", "4K,,16K", "0", "-1M"}) {
        auto run = prism::test::run_prism(std::string("bandwidth --sizes '") + sizes + "'");
        EXPECT_NE(run.exit_code, 0) << sizes;
        EXPECT_EQ(line_count(run.output), 1) << sizes << ":\n" << run.output;
        EXPECT_NE(run.output.find("--sizes"), std::string::npos) << sizes << ": " << run.output;
    }
}

// Without matplotlib the command names the package to install, before it measures anything, and writes nothing.
TEST(Bandwidth, PlotWithoutMatplotlibSaysWhatToInstall) {
    fs::path plot = prism::test::temp_dir("bandwidth") / "never.png";
    fs::remove(plot);
    auto run = prism::test::run_prism("bandwidth --sizes 4K --plot '" + plot.string() + "'",
                                      "env PRISM_PYTHON=/nonexistent/python3");
    EXPECT_NE(run.exit_code, 0);
    EXPECT_EQ(line_count(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("--plot"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("apt-get install python3-matplotlib"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("measuring"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(plot));
}

TEST(Bandwidth, PlotMustBeAPng) {
    auto run = prism::test::run_prism("bandwidth --sizes 4K --plot chart.pdf");
    EXPECT_NE(run.exit_code, 0);
    EXPECT_EQ(line_count(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("--plot: expected a .png"), std::string::npos) << run.output;
}

// A value PRISM_VULKAN_STAGING does not take stops the command before it measures anything.
TEST(Bandwidth, BadStagingSettingFailsWithOneLine) {
    auto run = prism::test::run_prism("bandwidth --sizes 4K", "env PRISM_VULKAN_STAGING=pinned");
    EXPECT_NE(run.exit_code, 0);
    EXPECT_EQ(line_count(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("PRISM_VULKAN_STAGING='pinned' is not one of uncached, cached, host, host-4k"),
              std::string::npos)
        << run.output;
}

// PRISM_VULKAN_COPY_REGIONS takes a whole number from 1 to 64; anything else stops the command before it measures.
TEST(Bandwidth, BadCopyRegionsSettingFailsWithOneLine) {
    for (const char* value : {"0", "65", "4x", "-1"}) {
        auto run =
            prism::test::run_prism("bandwidth --sizes 4K", std::string("env PRISM_VULKAN_COPY_REGIONS=") + value);
        EXPECT_NE(run.exit_code, 0) << value;
        EXPECT_EQ(line_count(run.output), 1) << run.output;
        EXPECT_NE(run.output.find(std::string("PRISM_VULKAN_COPY_REGIONS='") + value +
                                  "' is not a whole number from 1 to 64"),
                  std::string::npos)
            << run.output;
    }
}

#ifdef PRISM_HAVE_VULKAN
// `prism bandwidth --sizes <sizes>` on the Vulkan devices with `env` before it, its JSON parsed; null (and a failure
// recorded) when it did not run or wrote no JSON.
json vulkan_bandwidth(const std::string& sizes, const std::string& env, const std::string& file_name) {
    set_runtime_dir();
    fs::path file = prism::test::temp_dir("bandwidth-vulkan") / file_name;
    auto run = prism::test::run_prism(
        "bandwidth --sizes " + sizes + " --repeats 2 --device vulkan: --json '" + file.string() + "'", env);
    if (run.exit_code != 0) {
        ADD_FAILURE() << env << ": exit " << run.exit_code << "\n" << run.output;
        return nullptr;
    }
    std::ifstream in(file);
    json result = json::parse(in, nullptr, false);
    if (!result.is_object() || result["devices"].empty()) {
        ADD_FAILURE() << env << ": no result with a device\n" << run.output;
        return nullptr;
    }
    return result;
}

// PRISM_VULKAN_COPY_REGIONS=3: every Vulkan copy is three regions, at two sizes that three does not divide (the last
// region is the shorter); each copy's data check passes (a failed one is dropped), and the device says how it
// copied.
TEST(Bandwidth, VulkanCopiesInSeveralRegions) {
    json result = vulkan_bandwidth("4K,1M", "env PRISM_VULKAN_COPY_REGIONS=3", "regions.json");
    if (result.is_null()) return;
    bool found = false;
    for (const json& device : result["devices"]) {
        if (device["api"] != "vulkan") continue;
        found = true;
        EXPECT_NE(device["details"].dump().find("copies up to 3 regions of equal size"), std::string::npos)
            << device["details"].dump();
        // The pinned copies and the device-to-device one, at both sizes.
        std::set<std::string> copied;
        for (const json& m : device["measurements"])
            if (m["memory"] != "pageable")
                copied.insert(m["direction"].get<std::string>() + " " + std::to_string(m["bytes"].get<size_t>()));
        for (const char* direction : {"h2d", "d2h", "d2d"})
            for (size_t bytes : {size_t(4096), size_t(1) << 20})
                EXPECT_TRUE(copied.count(std::string(direction) + " " + std::to_string(bytes)))
                    << direction << " " << bytes;
    }
    EXPECT_TRUE(found) << result.dump();
}

// PRISM_VULKAN_STAGING=host and host-4k: the pinned copies go through the application's memory imported with
// VK_EXT_external_memory_host (lavapipe has it); the copies' data checks pass, and the device says how much of
// the staging memory the kernel backed with huge pages: none where they were refused.
TEST(Bandwidth, VulkanStagesThroughImportedHostMemory) {
    for (const char* staging : {"host", "host-4k"}) {
        json result =
            vulkan_bandwidth("4M", std::string("env PRISM_VULKAN_STAGING=") + staging, std::string(staging) + ".json");
        if (result.is_null()) continue;
        bool found = false;
        for (const json& device : result["devices"]) {
            if (device["api"] != "vulkan") continue;
            EXPECT_TRUE(device["notes"].empty()) << staging << ": " << device["notes"].dump();
            std::set<std::string> pinned;
            for (const json& m : device["measurements"])
                if (m["memory"] == "pinned") pinned.insert(m["direction"].get<std::string>());
            // A copy whose data check fails is dropped: both directions there means both came back intact.
            EXPECT_EQ(pinned, (std::set<std::string>{"h2d", "d2h"})) << staging;
            std::string details = device["details"].dump();
            found = details.find("imported with VK_EXT_external_memory_host") != std::string::npos;
            EXPECT_TRUE(found) << staging << ": " << details;
            if (std::string(staging) == "host-4k")
                EXPECT_NE(details.find("0 of 8 MiB"), std::string::npos) << details;
            else
                EXPECT_NE(details.find("huge pages asked for"), std::string::npos) << details;
        }
        EXPECT_TRUE(found) << "no Vulkan device in\n" << result.dump();
    }
}
#endif

TEST(Bandwidth, UnknownApiFailsWithOneLine) {
    auto run = prism::test::run_prism("bandwidth --api metal --sizes 4K");
    EXPECT_NE(run.exit_code, 0);
    EXPECT_EQ(line_count(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("metal"), std::string::npos) << run.output;
}

}  // namespace
