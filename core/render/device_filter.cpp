#include "core/render/device_filter.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <limits>

namespace prism {

std::optional<size_t> device_index(const std::string& filter) {
    if (filter.empty() || !std::all_of(filter.begin(), filter.end(), [](unsigned char c) { return std::isdigit(c); }))
        return std::nullopt;
    size_t index = 0;
    auto [end, error] = std::from_chars(filter.data(), filter.data() + filter.size(), index);
    if (error != std::errc() || end != filter.data() + filter.size()) return std::numeric_limits<size_t>::max();
    return index;
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

bool name_matches(const std::string& name, const std::string& filter) {
    return lowercase(name).find(lowercase(filter)) != std::string::npos;
}

}  // namespace prism
