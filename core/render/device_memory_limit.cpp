#include "core/render/device_memory_limit.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>

#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism {

std::optional<size_t> device_memory_limit() {
    std::optional<std::string> text = setting(Setting::DeviceMemoryLimit);
    if (!text || text->empty()) return std::nullopt;
    const std::string& value = *text;
    if (!std::all_of(value.begin(), value.end(), [](unsigned char c) { return std::isdigit(c); }))
        throw Error("PRISM_DEVICE_MEMORY_LIMIT='" + value + "' is not a byte count");
    try {
        return static_cast<size_t>(std::stoull(value));
    } catch (const std::exception&) {
        throw Error("PRISM_DEVICE_MEMORY_LIMIT='" + value + "' is out of range");
    }
}

}  // namespace prism
