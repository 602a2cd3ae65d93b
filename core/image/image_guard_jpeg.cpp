#include "core/image/image_guard_formats.h"

#include "core/util/error.h"

namespace prism::image_guard {

size_t jpeg_start_of_image(std::span<const uint8_t> bytes) {
    if (bytes.empty() || bytes[0] != 0xff) return 0;
    size_t at = 1;
    while (at < bytes.size() && bytes[at] == 0xff) ++at;
    return at < bytes.size() && bytes[at] == 0xd8 ? at : 0;
}

namespace {

// The frame types (SOFn markers) stb_image does not decode, by what they are; nullptr for the rest.
const char* unsupported_frame(uint8_t marker) {
    switch (marker) {
        case 0xc3: return "lossless";
        case 0xc5:
        case 0xc6:
        case 0xc7: return "hierarchical";
        case 0xc9:
        case 0xca:
        case 0xcb: return "arithmetic-coded";
        case 0xcd:
        case 0xce:
        case 0xcf: return "hierarchical arithmetic-coded";
        default: return nullptr;
    }
}

}  // namespace

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
    bool defined[2][4] = {};  // [DC, AC][table id]
    size_t at = jpeg_start_of_image(bytes) + 1;
    while (at + 1 < bytes.size()) {
        if (bytes[at] != 0xff) {  // entropy-coded data, or junk stb skips the same way
            ++at;
            continue;
        }
        const uint8_t marker = bytes[at + 1];
        if (marker == 0xff) {  // fill byte
            ++at;
            continue;
        }
        if (marker == 0x00 || (marker >= 0xd0 && marker <= 0xd7) || marker == 0x01) {  // stuffing, RSTn, TEM
            at += 2;
            continue;
        }
        if (marker == 0xd9) return;  // EOI
        const size_t segment_end = at + 2 + (byte(at + 2) << 8 | byte(at + 3));
        if (marker == 0xc2) progressive = true;              // the only progressive frame type stb decodes
        if (const char* coding = unsupported_frame(marker))  // a valid file stb cannot decode: not "corrupt"
            throw file_error(name, std::string(coding) +
                                       " JPEG is not supported (textures: baseline or progressive, Huffman-coded)");
        if ((marker == 0xc0 || marker == 0xc1 || marker == 0xc2) && byte(at + 4) != 8)
            throw file_error(name, std::to_string(byte(at + 4)) + "-bit JPEG is not supported (8-bit samples only)");
        if (marker == 0xc4) {  // DHT: tables of [class/id][16 counts][values] until the declared length
            for (size_t table = at + 4; table < segment_end && table < bytes.size();) {
                size_t codes = 0;
                for (size_t i = 1; i <= 16; ++i) codes += byte(table + i);
                if (codes > 256)
                    throw corrupt("a Huffman table declares " + std::to_string(codes) + " codes; at most 256 exist");
                const size_t kind = byte(table) >> 4, id = byte(table) & 15;
                if (kind <= 1 && id <= 3) defined[kind][id] = true;  // stb refuses other ids itself
                table += 17 + codes;
            }
        }
        if (marker == 0xda) {  // SOS: [count][(component, DC<<4 | AC) x count][Ss][Se][Ah<<4 | Al]
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
        at = segment_end;  // after SOS the scan's data follows and is skipped above
    }
}

// A JPEG codes every 8x8 block of its most finely sampled component (width/8 x height/8 of them) with at least one
// bit (a one-bit DC code in the first DC scan; baseline needs two), so a file holds at most 512 pixels per byte. stb
// fills a JPEG that ends early with grey: a few bytes claiming 8192x8192 would decode to 64M pixels of nothing.
void check_jpeg_size(std::span<const uint8_t> bytes, const std::string& name, int width, int height) {
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    if (pixels > 512 * uint64_t(bytes.size()))
        throw file_error(name, "truncated JPEG (" + std::to_string(width) + "x" + std::to_string(height) +
                                   " pixels need at least " + std::to_string(pixels / 512) + " bytes; the file has " +
                                   std::to_string(bytes.size()) + ")");
}

}  // namespace prism::image_guard
