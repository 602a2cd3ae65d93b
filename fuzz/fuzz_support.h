// What every fuzz target shares. The loaders take paths (they find MTL files, glTF buffers and textures beside
// the file), so each input is written into a private scratch folder and loaded from there. Every input is held to
// the project rule for bad input: it either loads or ends in one prism::Error whose message is one line naming a
// file; another exception type, a crash, a hang or a sanitizer report is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <utility>

namespace prism::fuzz {

// This process's scratch folder, created on first use under $TMPDIR (else /tmp) with the fixtures below, and
// removed at exit. Fixtures: tex.png (4x4 texture), tri.ply, tri.obj + tri.mtl (textured), tri.gltf + tri.bin,
// sky/ (a cube map of six 2x2 faces) and sky.hdr (a 4x2 equirect map): what scene files and MTL/glTF inputs
// may refer to by name (the dictionaries list these names).
const std::filesystem::path& scratch_dir();

void write_file(const std::filesystem::path& path, std::string_view bytes);
inline std::string_view as_text(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// Splits a two-file input (OBJ + MTL, .gltf + .bin) at the first "\n<separator>\n": one fuzzer input reaches both
// files and their interplay. Without the separator the whole input is the first file and found is false.
struct TwoFiles {
    std::string_view first;
    std::string_view second;
    bool found = false;
};
TwoFiles split_two_files(std::string_view input, std::string_view separator);

// The two files of one input written as `main` and `companion` in the scratch folder (without the separator the
// companion is removed: a missing MTL or .bin is an input too), then `main` loaded and built (load_and_build).
void load_two_files(const uint8_t* data, size_t size, std::string_view separator, const std::string& main,
                    const std::string& companion);

// The whole `prism render` path up to the upload: load_scene (loader, validation, framing) and
// build_device_scene (BVHs, texel arrays). Bad input must end in prism::Error; checked as above.
void load_and_build(const std::filesystem::path& scene_file);
// The same, letting prism::Error through to the caller's expect_clean_outcome.
void load_and_build_or_throw(const std::filesystem::path& scene_file);

// Runs `load`, accepting only success or a well-formed prism::Error; aborts (a libFuzzer finding) otherwise.
template <typename Load>
void expect_clean_outcome(Load&& load);

// Aborts with `what` when an error message breaks the rule (empty, several lines, or not "<file>: <cause>").
void check_error_message(const char* message);
[[noreturn]] void report_escaped_exception(const char* type, const char* message);

}  // namespace prism::fuzz

#include "core/util/error.h"

template <typename Load>
void prism::fuzz::expect_clean_outcome(Load&& load) {
    try {
        std::forward<Load>(load)();
    } catch (const prism::Error& error) {
        check_error_message(error.what());
    } catch (const std::exception& error) {
        report_escaped_exception("std::exception", error.what());
    } catch (...) {
        report_escaped_exception("unknown exception", "");
    }
}
