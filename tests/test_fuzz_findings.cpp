// Regression tests for what the fuzzers (fuzz/, scripts/fuzz.sh) found. Each input in tests/data/fuzz is the
// finding cut down to its cause (not a copy of a shared asset); each test holds the loader to the project rule:
// one prism::Error naming the file and the cause, and from the command line one line, exit 1..127, no image.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/scene_loader.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

fs::path finding(const std::string& name) { return fs::path(PRISM_SOURCE_DIR) / "tests" / "data" / "fuzz" / name; }

std::string load_error(const fs::path& file) {
    return prism::test::error_message([&] { (void)prism::load_scene(file.string()); });
}

}  // namespace

// fuzz_ply: a header token with a CR and an escape sequence in it was quoted raw, so the one-line report
// carried a carriage return (the terminal overwrote the line) and a clear-screen sequence.
TEST(FuzzFindings, ControlBytesQuotedFromAFileAreEscaped) {
    const fs::path file = finding("ply-control-bytes-in-header.ply");
    const std::string message = load_error(file);
    EXPECT_EQ(message, file.string() + ":3: bad element count '3\\x0dtexture\\x1b[2J'");
    prism::test::expect_clean_failure(file.string(), "bad element count");
    const prism::test::CommandResult r = prism::test::run_prism("info --scene '" + file.string() + "'");
    EXPECT_EQ(r.output.find_first_of("\r\x1b"), std::string::npos) << r.output;
}

TEST(FuzzFindings, ErrorMessagesNeverCarryControlCharacters) {
    EXPECT_STREQ(prism::Error(std::string("a\rb\nc\0d\x7f", 8)).what(), "a\\x0db\\x0ac\\x00d\\x7f");
    EXPECT_STREQ(prism::file_error("f.ply", "caf\xc3\xa9 \t").what(), "f.ply: caf\xc3\xa9 \\x09");   // UTF-8 stays
}

// fuzz_scene_json: a number beyond double's range is nlohmann's out_of_range (406), not a parse_error; it escaped
// the loader as a bare library message without the file's name.
TEST(FuzzFindings, SceneFileNumberOutOfRangeNamesTheFile) {
    const fs::path file = finding("scene-number-overflow.json");
    const std::string message = load_error(file);
    EXPECT_EQ(message.rfind(file.string() + ": invalid JSON: ", 0), 0u) << message;
    EXPECT_NE(message.find("1e999"), std::string::npos) << message;
    prism::test::expect_clean_failure(file.string(), "scene-number-overflow.json: invalid JSON");
}
