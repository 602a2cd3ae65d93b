#include "core/image_guard.h"

#include <climits>
#include <cstring>
#include <string_view>

#include <stb_image.h>

#include "core/error.h"

namespace prism {
namespace {

bool starts_with(std::span<const uint8_t> bytes, std::string_view prefix) {
    return bytes.size() >= prefix.size() && std::memcmp(bytes.data(), prefix.data(), prefix.size()) == 0;
}

// stb_image tries its decoders in turn; these are the signatures of the ones Prism does not offer.
const char* unsupported_format(std::span<const uint8_t> bytes) {
    if (starts_with(bytes, "GIF8")) return "GIF";
    if (starts_with(bytes, "8BPS")) return "Photoshop (PSD)";
    if (starts_with(bytes, "\x53\x80\xf6\x34")) return "Softimage PIC";
    if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '6')) return "PNM";
    return nullptr;
}

// stb_image takes a file for a JPEG when it starts with 0xff, any number of 0xff fill bytes, then SOI (0xd8):
// the index of that 0xd8, or 0 when the file is no JPEG to stb.
size_t jpeg_start_of_image(std::span<const uint8_t> bytes) {
    if (bytes.empty() || bytes[0] != 0xff) return 0;
    size_t at = 1;
    while (at < bytes.size() && bytes[at] == 0xff) ++at;
    return at < bytes.size() && bytes[at] == 0xd8 ? at : 0;
}

// JPEG: walks the marker segments the way stb_image does (declared lengths; over the entropy-coded data between
// scans to the next marker) and checks the Huffman tables, for two faults of stb_image 2.27 that upstream 2.28
// fixed. Bytes past the end read as 0, as stb_image reads them.
// - A table whose 16 code counts add up to more than 256 codes: stb writes past its arrays (UBSan:
//   stbi__build_huffman, index 257 of 257).
// - A scan that decodes with a table no DHT segment defined: stb's tables live in uninitialised memory, and
//   decoding with one indexes out of bounds (UBSan: stbi__jpeg_huff_decode, index 1633110942 of 256). Which tables
//   a scan decodes with follows stb: baseline scans both; progressive DC first scans the DC table, DC refinement
//   none, AC scans the AC table.
void check_jpeg(std::span<const uint8_t> bytes, const std::string& name) {
    auto byte = [&](size_t i) -> size_t { return i < bytes.size() ? bytes[i] : 0; };
    auto corrupt = [&](const std::string& cause) { return file_error(name, "corrupt JPEG (" + cause + ")"); };
    bool progressive = false;
    bool defined[2][4] = {};   // [DC, AC][table id]
    size_t at = jpeg_start_of_image(bytes) + 1;
    while (at + 1 < bytes.size()) {
        if (bytes[at] != 0xff) {   // entropy-coded data, or junk stb skips the same way
            ++at;
            continue;
        }
        const uint8_t marker = bytes[at + 1];
        if (marker == 0xff) {   // fill byte
            ++at;
            continue;
        }
        if (marker == 0x00 || (marker >= 0xd0 && marker <= 0xd7) || marker == 0x01) {   // stuffing, RSTn, TEM
            at += 2;
            continue;
        }
        if (marker == 0xd9) return;   // EOI
        const size_t segment_end = at + 2 + (byte(at + 2) << 8 | byte(at + 3));
        if (marker == 0xc2) progressive = true;   // the only progressive frame type stb decodes
        if (marker == 0xc4) {   // DHT: tables of [class/id][16 counts][values] until the declared length
            for (size_t table = at + 4; table < segment_end && table < bytes.size();) {
                size_t codes = 0;
                for (size_t i = 1; i <= 16; ++i) codes += byte(table + i);
                if (codes > 256)
                    throw corrupt("a Huffman table declares " + std::to_string(codes) + " codes; at most 256 exist");
                const size_t kind = byte(table) >> 4, id = byte(table) & 15;
                if (kind <= 1 && id <= 3) defined[kind][id] = true;   // stb refuses other ids itself
                table += 17 + codes;
            }
        }
        if (marker == 0xda) {   // SOS: [count][(component, DC<<4 | AC) x count][Ss][Se][Ah<<4 | Al]
            const size_t count = byte(at + 4);
            const size_t spectral_start = byte(at + 5 + 2 * count), high_bit = byte(at + 7 + 2 * count) >> 4;
            const bool uses_dc = !progressive || (spectral_start == 0 && high_bit == 0);
            const bool uses_ac = !progressive || spectral_start != 0;
            for (size_t c = 0; c < count; ++c) {
                const size_t dc = byte(at + 6 + 2 * c) >> 4, ac = byte(at + 6 + 2 * c) & 15;
                if ((uses_dc && dc <= 3 && !defined[0][dc]) || (uses_ac && ac <= 3 && !defined[1][ac]))
                    throw corrupt("a scan decodes with a Huffman table no DHT segment defined");
            }
        }
        at = segment_end;   // after SOS the scan's data follows and is skipped above
    }
}

// PNG: each chunk's declared length must fit in what is left of the file. stb_image 2.27 grows its IDAT buffer to
// the declared length before reading it (fuzz_image: a 2 KB file made it allocate 1.5 GB); with this check it
// never holds more than the file's size. A missing CRC after the last chunk is tolerated, as stb tolerates it.
void check_png(std::span<const uint8_t> bytes, const std::string& name) {
    size_t at = 8;   // after the signature
    while (at + 8 <= bytes.size()) {
        const uint64_t length = uint64_t(bytes[at]) << 24 | uint64_t(bytes[at + 1]) << 16 |
                                uint64_t(bytes[at + 2]) << 8 | bytes[at + 3];
        const std::string type(reinterpret_cast<const char*>(bytes.data() + at + 4), 4);
        const uint64_t left = bytes.size() - (at + 8);
        if (length > left)
            throw file_error(name, "corrupt PNG (a chunk declares " + std::to_string(length) + " bytes; " +
                                       std::to_string(left) + " are left in the file)");
        if (type == "IEND") return;
        at += 12 + length;
    }
}

}  // namespace

void check_encoded_image(std::span<const uint8_t> bytes, const std::string& name) {
    if (const char* format = unsupported_format(bytes))
        throw file_error(name, std::string("unsupported image format ") + format +
                                   " (textures: PNG, JPEG, BMP, TGA or Radiance HDR)");
    if (jpeg_start_of_image(bytes) != 0) check_jpeg(bytes, name);
    if (starts_with(bytes, "\x89PNG\r\n\x1a\n")) check_png(bytes, name);
    if (bytes.size() > size_t(INT_MAX)) throw file_error(name, "image file too large");
    int width = 0, height = 0, channels = 0;
    // stbi_info reads headers only; images it cannot size fail in the decoder with stb's own reason.
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels)) return;
    if (width > kMaxTextureSide || height > kMaxTextureSide || int64_t(width) * height > kMaxTexturePixels)
        throw file_error(name, "image is " + std::to_string(width) + "x" + std::to_string(height) +
                                   " pixels; Prism takes textures up to " + std::to_string(kMaxTextureSide) +
                                   " on a side and " + std::to_string(kMaxTexturePixels >> 20) + "M pixels");
}

}  // namespace prism
