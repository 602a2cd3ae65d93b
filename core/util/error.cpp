#include "core/util/error.h"

namespace prism {

std::string one_line(std::string_view text) {
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte != 0x7f) {
            out += c;
            continue;
        }
        out += "\\x";
        out += kHex[byte >> 4];
        out += kHex[byte & 15];
    }
    return out;
}

std::string shorten(std::string_view text, size_t max) {
    if (text.size() <= max) return std::string(text);
    return std::string(text.substr(0, max)) + "... (" + std::to_string(text.size()) + " characters)";
}

std::string library_message(std::string_view text, std::string_view fallback) {
    std::string_view line;
    while (!text.empty()) {
        const size_t end = text.find('\n');
        line = text.substr(0, end);
        text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
        if (!line.empty()) break;
    }
    std::string cleaned;
    for (size_t i = 0; i < line.size();) {
        // "[json.exception.<kind>.<id>] " names nlohmann's exception class, which tells the user nothing.
        if (line.substr(i).starts_with("[json.exception.")) {
            const size_t close = line.find("] ", i);
            if (close != std::string_view::npos) {
                i = close + 2;
                continue;
            }
        }
        cleaned += line[i++];
    }
    if (cleaned.empty()) return std::string(fallback);
    return shorten(cleaned, 200);
}

}  // namespace prism
