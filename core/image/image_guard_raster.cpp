// TGA, BMP and Radiance HDR: stb_image reads their pixels byte by byte and reads 0 past the end of the file. A
// 33-byte RLE TGA "decoded" to 3072x12832 pixels of nothing (fuzz_image: a timeout under the sanitizers), and an
// HDR whose run-length data ends inside a scanline makes stb 2.27 loop for ever on zero-length runs
// (CVE-2021-42715, fixed upstream in 2.28). A file too short for the pixels its header declares is refused as
// truncated, as the README promises for every format.
#include <string_view>

#include "core/util/error.h"
#include "core/image/image_guard_formats.h"

namespace prism::image_guard {
namespace {

uint64_t le16(std::span<const uint8_t> b, size_t at) { return at + 2 <= b.size() ? b[at] | b[at + 1] << 8 : 0; }
uint64_t le32(std::span<const uint8_t> b, size_t at) {
    return at + 4 <= b.size()
               ? uint64_t(b[at]) | uint64_t(b[at + 1]) << 8 | uint64_t(b[at + 2]) << 16 | uint64_t(b[at + 3]) << 24
               : 0;
}

[[noreturn]] void truncated(const std::string& name, const char* format, int width, int height, uint64_t needed,
                            uint64_t present) {
    throw file_error(name, std::string("truncated ") + format + " (" + std::to_string(width) + "x" +
                               std::to_string(height) + " pixels need at least " + std::to_string(needed) +
                               " bytes of pixel data; the file has " + std::to_string(present) + ")");
}

}  // namespace

// Header: id length, colour-map type and image type, colour-map length and entry bits, ..., bits per pixel.
// Uncompressed data is width x height pixels; run-length packets hold at most 128 pixels and a pixel each.
void check_tga(std::span<const uint8_t> bytes, const std::string& name, int width, int height) {
    if (bytes.size() < 18) return;  // stb refuses it
    const uint64_t map_bytes = bytes[1] ? le16(bytes, 5) * ((bytes[7] + 7u) / 8u) : 0;
    const uint64_t data = 18 + bytes[0] + map_bytes;
    const uint64_t pixel_bytes = (bytes[16] + 7u) / 8u;
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    const bool run_length = bytes[2] >= 8;
    const uint64_t needed = run_length ? (pixels + 127) / 128 * (1 + pixel_bytes) : pixels * pixel_bytes;
    const uint64_t present = bytes.size() > data ? bytes.size() - data : 0;
    if (needed > present) truncated(name, "TGA", width, height, needed, present);
}

// "BM", file size, reserved, pixel-data offset (10); header size (14); width, height (18, 22; 16-bit at 18, 20 in
// the 12-byte OS/2 header); bits per pixel (28, or 24); compression (30). Rows are padded to 4 bytes; the last
// row's padding may be missing. Run-length BMPs stb refuses itself.
void check_bmp(std::span<const uint8_t> bytes, const std::string& name, int width, int height) {
    const uint64_t header = le32(bytes, 14);
    const uint64_t bits = header == 12 ? le16(bytes, 24) : le16(bytes, 28);
    if (bits == 0 || (header != 12 && le32(bytes, 30) != 0 && le32(bytes, 30) != 3)) return;
    const uint64_t row = (uint64_t(width) * bits + 31) / 32 * 4;
    const uint64_t needed = row * (uint64_t(height) - 1) + (uint64_t(width) * bits + 7) / 8;
    const uint64_t data = std::max<uint64_t>(le32(bytes, 10), 14 + header);
    const uint64_t present = bytes.size() > data ? bytes.size() - data : 0;
    if (needed > present) truncated(name, "BMP", width, height, needed, present);
}

// Header lines up to an empty one, then the resolution line; pixels follow. Scanlines of width 8..32767 are
// run-length encoded: 2, 2, width (16 bits), then per channel runs (count > 128: one value repeated) and dumps
// (count values) until the width is filled. This walks them as stb does and stops where stb would stop; running
// out of bytes inside a scanline is where stb 2.27 spins. Flat data needs 4 bytes per pixel.
void check_hdr(std::span<const uint8_t> bytes, const std::string& name, int width, int height) {
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    size_t at = text.find('\n');  // the signature line
    while (at != std::string_view::npos && at + 1 < text.size() && text[at + 1] != '\n') at = text.find('\n', at + 1);
    if (at == std::string_view::npos || at + 1 >= text.size()) return;  // no header end: stb refuses it
    at = text.find('\n', at + 2);                                       // the resolution line
    if (at == std::string_view::npos) return;
    size_t pos = at + 1;
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    if (width < 8 || width >= 32768) {
        const uint64_t present = bytes.size() - pos;
        if (pixels * 4 > present) truncated(name, "HDR", width, height, pixels * 4, present);
        return;
    }
    // The least run-length data can take: per row a 4-byte header and, per channel, 2-byte runs of 127 pixels.
    const uint64_t least = uint64_t(height) * (4 + 4 * 2 * ((uint64_t(width) + 126) / 127));
    auto fail = [&] { truncated(name, "HDR", width, height, least, bytes.size() - (at + 1)); };
    for (int row = 0; row < height; ++row) {
        if (pos + 4 > bytes.size()) fail();
        if (bytes[pos] != 2 || bytes[pos + 1] != 2 || (bytes[pos + 2] & 0x80)) {  // stb reads flat pixels from here
            if (pixels * 4 > bytes.size() - pos) truncated(name, "HDR", width, height, pixels * 4, bytes.size() - pos);
            return;
        }
        if ((bytes[pos + 2] << 8 | bytes[pos + 3]) != width) return;  // stb refuses it
        pos += 4;
        for (int channel = 0; channel < 4; ++channel) {
            for (int filled = 0; filled < width;) {
                if (pos >= bytes.size()) fail();  // stb would read zero-length runs for ever
                int count = bytes[pos++];
                const bool run = count > 128;
                if (run) count -= 128;
                if (count > width - filled) return;  // stb refuses it
                pos += run ? 1 : size_t(count);
                filled += count;
            }
        }
    }
}

}  // namespace prism::image_guard
