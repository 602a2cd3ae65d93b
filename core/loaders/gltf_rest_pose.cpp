#include "core/loaders/gltf_rest_pose.h"

#include <cstdint>
#include <cstring>

#include <nlohmann/json.hpp>

namespace prism {
namespace {

constexpr uint32_t kGlbHeaderBytes = 12;
constexpr uint32_t kChunkHeaderBytes = 8;
constexpr uint32_t kChunkJson = 0x4E4F534Au;  // "JSON"

uint32_t read_u32(std::string_view bytes, size_t offset) {
    uint32_t value = 0;
    std::memcpy(&value, bytes.data() + offset, 4);
    return value;
}

void append_u32(std::string& out, uint32_t value) { out.append(reinterpret_cast<const char*>(&value), 4); }

}  // namespace

std::optional<RestPoseGltf> gltf_without_animation(std::string_view bytes, bool binary) {
    // The GLB container: a 12-byte header (magic, version, length), then chunks of (length, type, bytes), the JSON
    // chunk first. Anything else is left to tinygltf's own checks and messages.
    std::string_view json_text = bytes;
    size_t rest = bytes.size();  // where the chunks after the JSON chunk begin
    if (binary) {
        if (bytes.size() < kGlbHeaderBytes + kChunkHeaderBytes) return std::nullopt;
        const uint32_t length = read_u32(bytes, kGlbHeaderBytes);
        if (read_u32(bytes, kGlbHeaderBytes + 4) != kChunkJson ||
            length > bytes.size() - kGlbHeaderBytes - kChunkHeaderBytes)
            return std::nullopt;
        json_text = bytes.substr(kGlbHeaderBytes + kChunkHeaderBytes, length);
        rest = kGlbHeaderBytes + kChunkHeaderBytes + length;
    }
    // A cheap look first: most files have neither, and parsing a large .gltf's embedded buffers twice is not free.
    if (json_text.find("\"animations\"") == std::string_view::npos &&
        json_text.find("\"skins\"") == std::string_view::npos)
        return std::nullopt;
    nlohmann::json document = nlohmann::json::parse(json_text, nullptr, false);
    if (document.is_discarded() || !document.is_object()) return std::nullopt;
    const bool had_animations = document.erase("animations") > 0;
    const bool had_skins = document.erase("skins") > 0;
    if (!had_animations && !had_skins) return std::nullopt;

    std::string json = document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    RestPoseGltf out{{}, had_animations};
    if (!binary) {
        out.bytes = std::move(json);
        return out;
    }
    while (json.size() % 4) json += ' ';  // chunks are 4-byte aligned; JSON pads with spaces
    const std::string_view chunks = bytes.substr(rest);
    const uint64_t total = uint64_t(kGlbHeaderBytes) + kChunkHeaderBytes + json.size() + chunks.size();
    if (total > UINT32_MAX) return std::nullopt;
    out.bytes.reserve(size_t(total));
    out.bytes.append(bytes.substr(0, 8));  // magic and version as the file has them
    append_u32(out.bytes, uint32_t(total));
    append_u32(out.bytes, uint32_t(json.size()));
    append_u32(out.bytes, kChunkJson);
    out.bytes += json;
    out.bytes.append(chunks);
    return out;
}

}  // namespace prism
