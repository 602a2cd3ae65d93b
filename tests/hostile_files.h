// Hostile files made at run time, small on disk and huge when read: a gzip stream that inflates to gigabytes
// of blanks, and PNG images of any size (all zero pixels). Nothing of the kind is kept in the repository.
#pragma once

#include <cstdint>
#include <string>

#include <zlib.h>

namespace prism::test {

// A raw deflate block of `bytes` copies of `fill`, ending on a byte boundary with the dictionary reset
// (Z_FULL_FLUSH), so it can be repeated back to back and still decode.
inline std::string deflate_block(const std::string& bytes, int level = 9) {
    z_stream stream{};
    deflateInit2(&stream, level, Z_DEFLATED, -15, 9, Z_DEFAULT_STRATEGY);
    std::string out(deflateBound(&stream, bytes.size()) + 64, '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    deflate(&stream, Z_FULL_FLUSH);
    out.resize(out.size() - stream.avail_out);
    deflateEnd(&stream);
    return out;
}

inline std::string little_endian32(uint32_t value) {
    std::string out(4, '\0');
    for (int i = 0; i < 4; ++i) out[i] = static_cast<char>((value >> (8 * i)) & 255u);
    return out;
}

// A gzip file holding `prefix` and then `repeats` x `chunk` bytes of `fill`: one compressed block repeated, so
// 2 GiB of blanks take about 2 MB.
inline std::string gzip_bomb(const std::string& prefix, char fill, size_t chunk, size_t repeats) {
    const std::string block_text(chunk, fill);
    const std::string block = deflate_block(block_text);
    std::string out = std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00\x02\x03", 10);
    out += deflate_block(prefix);
    uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(prefix.data()), static_cast<uInt>(prefix.size()));
    const uLong block_crc = crc32(0L, reinterpret_cast<const Bytef*>(block_text.data()), static_cast<uInt>(chunk));
    for (size_t i = 0; i < repeats; ++i) {
        out += block;
        crc = crc32_combine(crc, block_crc, static_cast<z_off_t>(chunk));
    }
    out += std::string("\x03\x00", 2);  // a final, empty fixed-Huffman block
    out += little_endian32(static_cast<uint32_t>(crc));
    out += little_endian32(static_cast<uint32_t>(prefix.size() + chunk * repeats));
    return out;
}

inline std::string png_chunk(const std::string& type, const std::string& data) {
    std::string length(4, '\0');
    for (int i = 0; i < 4; ++i) length[i] = static_cast<char>((data.size() >> (8 * (3 - i))) & 255u);
    const std::string body = type + data;
    const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()));
    std::string crc_bytes(4, '\0');
    for (int i = 0; i < 4; ++i) crc_bytes[i] = static_cast<char>((crc >> (8 * (3 - i))) & 255u);
    return length + body + crc_bytes;
}

// An RGBA8 PNG of width x height transparent black pixels (a few hundred KB even at 8192x8192).
inline std::string blank_png(uint32_t width, uint32_t height) {
    std::string header;
    for (uint32_t value : {width, height})
        for (int i = 3; i >= 0; --i) header += static_cast<char>((value >> (8 * i)) & 255u);
    header += std::string("\x08\x06\x00\x00\x00", 5);
    const std::string raw(size_t(height) * (1 + size_t(width) * 4), '\0');  // filter byte 0 + pixels, per row
    uLongf size = compressBound(static_cast<uLong>(raw.size()));
    std::string compressed(size, '\0');
    compress2(reinterpret_cast<Bytef*>(compressed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
              static_cast<uLong>(raw.size()), 9);
    compressed.resize(size);
    return std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", header) + png_chunk("IDAT", compressed) +
           png_chunk("IEND", "");
}

}  // namespace prism::test
