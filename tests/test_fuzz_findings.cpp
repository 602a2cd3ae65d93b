// Regression tests for what the fuzzers (fuzz/, scripts/fuzz.sh) found. Each input in tests/data/fuzz is the
// finding cut down to its cause (not a copy of a shared asset); each test holds the loader to the project rule:
// one prism::Error naming the file and the cause, and from the command line one line, exit 1..127, no image.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "core/image/image_guard.h"
#include "core/image/image_io.h"
#include "core/loaders/scene_loader.h"
#include "tests/hostile_files.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

fs::path finding(const std::string& name) { return fs::path(PRISM_SOURCE_DIR) / "tests" / "data" / "fuzz" / name; }

std::string load_error(const fs::path& file) {
    return prism::test::error_message([&] { (void)prism::load_scene(file.string()); });
}

std::string texture_error(const fs::path& file) {
    return prism::test::error_message([&] { (void)prism::load_texture(file); });
}

// A scene file whose one material uses a copy of `texture` beside it (a scene reads only files in its folder):
// how an image reaches `prism render`.
fs::path scene_with_texture(const fs::path& texture) {
    const fs::path folder = prism::test::temp_dir("fuzz-findings");
    fs::copy_file(texture, folder / texture.filename(), fs::copy_options::overwrite_existing);
    const fs::path scene = folder / (texture.stem().string() + ".json");
    std::ofstream(scene) << R"({"materials": {"m": {"textures": [{"file": ")" << texture.filename().string()
                         << R"("}]}}})";
    return scene;
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

// fuzz_ply: an element with no properties that declares 4,294,967,295 records was skipped record by record, reading
// nothing each time (a sanitizer build spent 19 s). It has nothing to read: the file loads at once.
TEST(FuzzFindings, PlyElementWithoutPropertiesIsSkippedWhole) {
    const fs::path file = finding("ply-element-without-properties-declares-4294967295.ply");
    prism::Scene scene = prism::load_scene(file.string());
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].triangles.size(), 1u);
    EXPECT_EQ(scene.meshes[0].positions.size(), 3u);
}

TEST(FuzzFindings, ErrorMessagesNeverCarryControlCharacters) {
    EXPECT_STREQ(prism::Error(std::string("a\rb\nc\0d\x7f", 8)).what(), "a\\x0db\\x0ac\\x00d\\x7f");
    EXPECT_STREQ(prism::file_error("f.ply", "caf\xc3\xa9 \t").what(), "f.ply: caf\xc3\xa9 \\x09");  // UTF-8 stays
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

// fuzz_obj: a skin-weight line (vw) whose joint is 1e39000: tinyobjloader converts the joint to int, undefined for
// a value past int's range (UBSan: float-cast-overflow in tinyobj::LoadObj). The OBJ check refuses the value first.
TEST(FuzzFindings, ObjSkinWeightOutOfIntRangeIsRefused) {
    const fs::path file = finding("obj-skin-weight-joint-1e39000.obj");
    EXPECT_EQ(load_error(file),
              file.string() + ":5: skin weight (vw) value '1e39000' is not a number within +-2147483647");
    prism::test::expect_clean_failure(file.string(), "skin weight (vw) value '1e39000'");
}

// fuzz_image: a JPEG Huffman table whose 16 code counts add up to more than 256 made Debian's stb_image (2.27)
// write past its code-length array (UBSan: stbi__build_huffman, index 257 of 257); also when the table is cut off
// by the end of the file (stb_image reads the missing counts as 0 and still overflows).
TEST(FuzzFindings, JpegHuffmanTableWithTooManyCodesIsRefused) {
    for (const char* name : {"jpeg-huffman-272-codes.jpg", "jpeg-huffman-table-cut-short.jpg"}) {
        const fs::path file = finding(name);
        const std::string message = texture_error(file);
        EXPECT_EQ(message.rfind(file.string() + ": corrupt JPEG (a Huffman table declares ", 0), 0u) << message;
        prism::test::expect_clean_failure(scene_with_texture(file).string(), name);
    }
}

// fuzz_image, past the first guard: stb_image takes a file starting with any number of 0xff fill bytes before
// SOI for a JPEG; the guard only looked for 0xff 0xd8 at the start, and this one went through to the same overflow.
TEST(FuzzFindings, JpegWithFillBytesBeforeSoiIsGuardedToo) {
    const fs::path file = finding("jpeg-fill-bytes-before-soi.jpg");
    EXPECT_EQ(texture_error(file),
              file.string() + ": corrupt JPEG (a Huffman table declares 272 codes; at most 256 exist)");
}

// fuzz_image: a progressive JPEG whose AC scan decodes with an AC table no DHT segment defined. stb_image 2.27
// keeps its tables in uninitialised memory and indexed out of bounds with whatever was there (UBSan:
// stbi__jpeg_huff_decode, index 1633110942 of 256; what this file does to bare stb depends on that memory).
TEST(FuzzFindings, JpegScanWithAnUndefinedHuffmanTableIsRefused) {
    const fs::path file = finding("jpeg-scan-uses-undefined-huffman-table.jpg");
    EXPECT_EQ(texture_error(file),
              file.string() + ": corrupt JPEG (a scan decodes with a Huffman table no DHT segment defined)");
    prism::test::expect_clean_failure(scene_with_texture(file).string(), "no DHT segment defined");
}

// fuzz_image (CI's 60 s run): a baseline JPEG whose scan ends (a marker) while a coefficient still needs 8 more bits
// than the buffer holds. stb_image 2.27 consumes them anyway, its bit count goes to -8, and the next top-up shifts
// by 32 (UBSan: stbi__grow_buffer_unsafe, shift exponent 32). Past the marker stb shifts in only zero bytes, so the
// shift's value is 0 whatever the CPU makes of the count: the file decodes exactly as the same scan followed by
// zero bytes does, which is what this test holds stb to. fuzz/stb_image.ignorelist lifts that one check there.
TEST(FuzzFindings, JpegScanEndingInsideACoefficientDecodesAsZeroBits) {
    const fs::path file = finding("jpeg-scan-ends-inside-a-coefficient.jpg");
    std::ifstream in(file, std::ios::binary);
    std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    const prism::Texture texture = prism::load_texture_from_memory(bytes, file.string());
    ASSERT_EQ(texture.width, 8);
    ASSERT_EQ(texture.height, 8);
    // The scan's four bytes end just before the EOI marker; give the decoder the zero bits it read as real bytes.
    const uint8_t eoi[] = {0xff, 0xd9};
    const auto end_of_image = std::search(bytes.begin(), bytes.end(), std::begin(eoi), std::end(eoi));
    ASSERT_NE(end_of_image, bytes.end());
    std::vector<uint8_t> padded(bytes.begin(), end_of_image);
    padded.insert(padded.end(), 16, 0);
    padded.insert(padded.end(), end_of_image, bytes.end());
    const prism::Texture zero_padded = prism::load_texture_from_memory(padded, "zero-padded");
    EXPECT_EQ(texture.texels, zero_padded.texels);
    EXPECT_NE(texture.texels, std::vector<uint32_t>(64, texture.texels[0]));  // the coefficients did decode
}

// (reading stb 2.28's fixes) A JPEG's DC coefficient is the running sum of its blocks' differences times the
// quantiser, in int, stored as a short: two blocks of +32767 with a 16-bit quantiser of 65535 overflow int (UBSan:
// stbi__jpeg_decode_block, 65534 * 65535). The short keeps the product's low 16 bits, which wrapping gives exactly:
// the first block's DC is -32767 (black), the second's 2 (mid grey). The fuzz build lifts that check there.
TEST(FuzzFindings, JpegDcCoefficientOverflowKeepsTheLow16Bits) {
    const prism::Texture texture = prism::load_texture(finding("jpeg-dc-coefficient-overflows-int.jpg"));
    ASSERT_EQ(texture.width, 16);
    ASSERT_EQ(texture.height, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            const int red = int(texture.texels[size_t(y * 16 + x)] & 0xff);
            if (x < 8)
                EXPECT_EQ(red, 0) << x << "," << y;
            else
                EXPECT_NEAR(red, 128, 1) << x << "," << y;
        }
}

// fuzz_image: stb_image names an unknown critical PNG chunk by its type; a type of four NUL bytes made the
// reason "" and the report "<file>: " with no cause.
TEST(FuzzFindings, ImageFailureWithoutAReasonStillGivesOne) {
    const fs::path file = finding("png-chunk-type-nul.png");
    EXPECT_EQ(texture_error(file), file.string() + ": unreadable image");
    prism::test::expect_clean_failure(scene_with_texture(file).string(), "png-chunk-type-nul.png: unreadable image");
}

// fuzz_image: stb_image grows its IDAT buffer to a chunk's declared length before reading it, so a 2 KB PNG made
// it allocate 1.5 GB (libFuzzer: out-of-memory, malloc(1559650380)). A chunk longer than the rest of the file is
// now refused before stb sees it.
TEST(FuzzFindings, PngChunkLongerThanTheFileIsRefused) {
    const fs::path file = finding("png-idat-claims-2gib.png");
    EXPECT_EQ(texture_error(file),
              file.string() + ": corrupt PNG (a chunk declares 2147483632 bytes; 10 are left in the file)");
    prism::test::expect_clean_failure(scene_with_texture(file).string(), "png-idat-claims-2gib.png: corrupt PNG");
}

// fuzz_glb: an image stored in a bufferView that reaches past its buffer. tinygltf 2.7 passes the view to the
// image callback unchecked, and copying it read past the buffer (ASan: heap-buffer-overflow in
// keep_encoded_image). The callback now checks the view against the buffer.
TEST(FuzzFindings, GlbImageBufferViewPastItsBufferIsRefused) {
    const fs::path file = finding("glb-image-view-past-buffer.glb");
    EXPECT_EQ(load_error(file), file.string() +
                                    ": image 0: bufferView 0 (offset 8, 100000 bytes) lies outside its "
                                    "buffer (16 bytes)");
    prism::test::expect_clean_failure(file.string(), "lies outside its buffer");
}

// fuzz_glb: a BIN chunk declaring 8 bytes with 4 left in the file. tinygltf 2.7 checks the chunk's length without
// its 8-byte header, so a buffer read from it ran past the end of the file (ASan heap-buffer-overflow in
// tinygltf::ParseBuffer).
TEST(FuzzFindings, GlbBinChunkLongerThanTheFileIsRefused) {
    const fs::path file = finding("glb-bin-chunk-overrun.glb");
    EXPECT_EQ(
        load_error(file),
        file.string() + ": the chunk after the JSON chunk declares 8 bytes; 4 are left in the file (truncated GLB)");
    prism::test::expect_clean_failure(file.string(), "declares 8 bytes");
}

// fuzz_gltf (CI's 60 s run): a meshopt buffer's `fallback` flag written as a number. The JSON edit made before
// tinygltf read it with nlohmann's json::value("fallback", false), which throws type_error.302 for a value that is
// not a boolean, and that std::exception left the loader instead of a prism::Error naming the file. Only the
// boolean true makes a fallback now; this buffer, without one and without a uri, is refused as any such buffer is.
TEST(FuzzFindings, GltfMeshoptFallbackFlagThatIsNotABooleanIsNoFallback) {
    const fs::path file = finding("gltf-meshopt-fallback-flag-is-a-number.gltf");
    EXPECT_EQ(load_error(file), file.string() + ": a buffer or image without a uri (only a .glb's own buffer may)");
    prism::test::expect_clean_failure(file.string(), "a buffer or image without a uri");
}

// fuzz_image (a timeout): stb_image reads TGA, BMP, HDR and JPEG pixels past the end of the file as zeros, so 33
// bytes of RLE TGA "decoded" to 3072x12832 pixels of nothing (over 10 s under the sanitizers, 0.6 s and 270 MB
// without). A file too short for the pixels its header declares is now truncated, in every format stb zero-fills;
// the BMP, JPEG and HDR inputs are made by hand for the same fault.
TEST(FuzzFindings, ImagesTooShortForTheirDeclaredSizeAreTruncated) {
    const std::pair<const char*, const char*> cases[] = {
        {"tga-rle-33-bytes-declares-39m-pixels.tga",
         "truncated TGA (3072x12832 pixels need at least 923904 bytes of pixel data; the file has 15)"},
        {"bmp-header-only-declares-4096x4096.bmp",
         "truncated BMP (4096x4096 pixels need at least 50331648 bytes of pixel data; the file has 0)"},
        {"jpeg-declares-8192x8192-in-156-bytes.jpg",
         "truncated JPEG (8192x8192 pixels need at least 131072 bytes; the file has 156)"},
    };
    for (const auto& [name, cause] : cases) {
        const fs::path file = finding(name);
        EXPECT_EQ(texture_error(file), file.string() + ": " + cause);
        prism::test::expect_clean_failure(scene_with_texture(file).string(), name);
    }
}

// fuzz_image (a timeout): a 281-byte BMP stored top down declares 16x-16777204 pixels; stbi_info reports the
// negative height as it is and the guard let it through, while stb's decoder takes the magnitude and decoded 268M
// pixels (1 GB). The guard now checks the magnitude against its limits.
TEST(FuzzFindings, TopDownBmpIsHeldToTheSizeLimits) {
    const fs::path file = finding("bmp-top-down-declares-16x16777204.bmp");
    const std::string error = texture_error(file);
    EXPECT_EQ(error.rfind(file.string() + ": image is 16x16777204 pixels; Prism takes textures up to ", 0), 0u)
        << error;
    prism::test::expect_clean_failure(scene_with_texture(file).string(), "16x16777204");
}

// Found by reading stb_image 2.27 against its upstream fixes while fixing the above (CVE-2021-42715), not by the
// fuzzer yet: an HDR whose run-length data ends inside a scanline makes stb read zero-length runs for ever, so a
// 49-byte environment map hung `prism render`. The guard walks the runs as stb does and stops at the end.
TEST(FuzzFindings, HdrRunLengthDataEndingInsideAScanlineIsTruncated) {
    const fs::path file = finding("hdr-rle-ends-inside-a-scanline.hdr");
    EXPECT_EQ(texture_error(file), file.string() +
                                       ": truncated HDR (8x1 pixels need at least 12 bytes of pixel "
                                       "data; the file has 4)");
    const fs::path folder = prism::test::temp_dir("fuzz-findings");
    fs::copy_file(file, folder / file.filename(), fs::copy_options::overwrite_existing);
    const fs::path scene = folder / "hdr-sky.json";
    std::ofstream(scene) << R"({"environment": {"equirect": ")" << file.filename().string() << R"("}})";
    prism::test::expect_clean_failure(scene.string(), "truncated HDR");
}

TEST(FuzzFindings, EveryImageInTheSharedScenesPassesTheGuard) {
    // The guard walks every JPEG marker segment: real files (progressive, EXIF, restart markers) must pass it, and
    // no real texture may be over the size limit.
    size_t checked = 0;
    std::error_code error;
    for (fs::recursive_directory_iterator it(prism::test::scenes_dir(), error), end; !error && it != end;
         it.increment(error)) {
        std::string extension = it->path().extension().string();
        for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (extension != ".png" && extension != ".jpg" && extension != ".jpeg" && extension != ".hdr") continue;
        std::ifstream file(it->path(), std::ios::binary);
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
        EXPECT_NO_THROW(prism::check_encoded_image(bytes, it->path().string())) << it->path();
        ++checked;
    }
    if (checked == 0) GTEST_SKIP() << "no images under " << prism::test::scenes_dir();
    EXPECT_GT(checked, 50u);
}

// fuzz_ply (issue 17's capped gzip reader): a .ply.gz whose inflated header is malformed. The header is judged
// while the stream inflates, and the error thrown from there left zlib's inflate state behind (LeakSanitizer:
// 39,928 bytes from inflateInit2_). The state is now released however reading ends; the file gets the header's
// own message, with its line.
TEST(FuzzFindings, GzipPlyWithAMalformedHeaderReportsTheHeader) {
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\npro\nend_header\n0 0 0\n";
    const fs::path file = prism::test::write_file("gzip-bad-header.ply.gz", prism::test::gzip_bomb(header, ' ', 1, 0));
    EXPECT_EQ(load_error(file), file.string() + ":4: unknown PLY header keyword 'pro'");
    prism::test::expect_clean_failure(file.string(), "unknown PLY header keyword 'pro'");
}
