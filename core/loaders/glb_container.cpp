#include "core/loaders/glb_container.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace prism {
namespace {

constexpr size_t kHeaderBytes = 12;
constexpr size_t kChunkHeaderBytes = 8;
constexpr uint32_t kChunkJson = 0x4E4F534Au;  // "JSON"

uint32_t read_u32(std::string_view bytes, size_t offset) {
    uint32_t value = 0;
    std::memcpy(&value, bytes.data() + offset, 4);
    return value;
}

void append_u32(std::string& out, uint32_t value) { out.append(reinterpret_cast<const char*>(&value), 4); }

}  // namespace

std::optional<GlbParts> split_glb(std::string_view bytes) {
    if (bytes.size() < kHeaderBytes + kChunkHeaderBytes) return std::nullopt;
    const uint32_t length = read_u32(bytes, kHeaderBytes);
    if (read_u32(bytes, kHeaderBytes + 4) != kChunkJson || length > bytes.size() - kHeaderBytes - kChunkHeaderBytes)
        return std::nullopt;
    const size_t rest = kHeaderBytes + kChunkHeaderBytes + length;
    return GlbParts{bytes.substr(0, 8), bytes.substr(kHeaderBytes + kChunkHeaderBytes, length), bytes.substr(rest)};
}

std::string_view glb_first_chunk(std::string_view bytes) {
    if (bytes.size() < kHeaderBytes + kChunkHeaderBytes) return {};
    const size_t start = kHeaderBytes + kChunkHeaderBytes;
    return bytes.substr(start, std::min<size_t>(read_u32(bytes, kHeaderBytes), bytes.size() - start));
}

std::optional<std::string> glb_second_chunk_overrun(std::string_view bytes) {
    std::optional<GlbParts> parts = split_glb(bytes);
    if (!parts || parts->rest.size() < kChunkHeaderBytes) return std::nullopt;
    const uint32_t length = read_u32(parts->rest, 0);
    const size_t left = parts->rest.size() - kChunkHeaderBytes;
    if (length <= left) return std::nullopt;
    return "the chunk after the JSON chunk declares " + std::to_string(length) + " bytes; " + std::to_string(left) +
           " are left in the file (truncated GLB)";
}

std::optional<std::string> join_glb(std::string_view header, std::string_view json, std::string_view rest) {
    const size_t padding = (4 - json.size() % 4) % 4;
    const uint64_t total = uint64_t(kHeaderBytes) + kChunkHeaderBytes + json.size() + padding + rest.size();
    if (total > UINT32_MAX) return std::nullopt;
    std::string out;
    out.reserve(size_t(total));
    out.append(header);
    append_u32(out, uint32_t(total));
    append_u32(out, uint32_t(json.size() + padding));
    append_u32(out, kChunkJson);
    out.append(json).append(padding, ' ');
    out.append(rest);
    return out;
}

}  // namespace prism
