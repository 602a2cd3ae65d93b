#include "bench/bandwidth/sizes.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>

#include "core/util/error.h"

namespace prism::bandwidth {

std::vector<size_t> default_sizes() {
    std::vector<size_t> sizes;
    for (size_t bytes = size_t(4) << 10; bytes <= size_t(1) << 30; bytes *= 4) sizes.push_back(bytes);
    return sizes;
}

static size_t parse_one(const std::string& item) {
    auto fail = [&](const std::string& cause) { return Error("--sizes: '" + item + "' " + cause); };
    size_t value = 0;
    const char* begin = item.data();
    const char* end = item.data() + item.size();
    auto [rest, error] = std::from_chars(begin, end, value);
    if (error != std::errc() || rest == begin) throw fail("is not a size (expected e.g. 4K, 16M, 1G or bytes)");
    std::string suffix(rest, end);
    std::transform(suffix.begin(), suffix.end(), suffix.begin(), [](unsigned char c) { return std::toupper(c); });
    int shift = 0;
    if (suffix.empty() || suffix == "B")
        shift = 0;
    else if (suffix == "K" || suffix == "KB" || suffix == "KIB")
        shift = 10;
    else if (suffix == "M" || suffix == "MB" || suffix == "MIB")
        shift = 20;
    else if (suffix == "G" || suffix == "GB" || suffix == "GIB")
        shift = 30;
    else
        throw fail("has an unknown unit (use K, M or G)");
    // 64 GiB keeps the element count of the copy kernel within 32 bits with room to spare.
    if (value == 0 || value > (size_t(64) << (30 - shift))) throw fail("is out of range (16 bytes to 64G)");
    size_t bytes = value << shift;
    if (bytes % 16 != 0) throw fail("is not a multiple of 16 bytes (the copy kernel moves 16-byte elements)");
    return bytes;
}

std::vector<size_t> parse_sizes(const std::string& text) {
    std::vector<size_t> sizes;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        std::string item = text.substr(start, comma - start);
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        if (item.empty()) throw Error("--sizes: empty entry in '" + text + "'");
        sizes.push_back(parse_one(item));
        start = comma + 1;
    }
    return sizes;
}

std::string format_size(size_t bytes) {
    const char* units[] = {"B", "K", "M", "G", "T"};
    int unit = 0;
    double value = static_cast<double>(bytes);
    while (value >= 1024 && unit < 4) {
        value /= 1024;
        ++unit;
    }
    char text[32];
    if (value == static_cast<double>(static_cast<size_t>(value)))
        std::snprintf(text, sizeof text, "%zu%s", static_cast<size_t>(value), units[unit]);
    else
        std::snprintf(text, sizeof text, "%.1f%s", value, units[unit]);
    return text;
}

}  // namespace prism::bandwidth
