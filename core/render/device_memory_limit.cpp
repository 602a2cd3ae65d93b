#include "core/render/device_memory_limit.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>

#include "core/util/error.h"

namespace prism {

std::optional<size_t> device_memory_limit() {
    const char* text = std::getenv("PRISM_DEVICE_MEMORY_LIMIT");
    if (!text || !*text) return std::nullopt;
    std::string value(text);
    if (!std::all_of(value.begin(), value.end(), [](unsigned char c) { return std::isdigit(c); }))
        throw Error("PRISM_DEVICE_MEMORY_LIMIT='" + value + "' is not a byte count");
    try {
        return static_cast<size_t>(std::stoull(value));
    } catch (const std::exception&) {
        throw Error("PRISM_DEVICE_MEMORY_LIMIT='" + value + "' is out of range");
    }
}

}  // namespace prism
