#include "viewer/backend_check.h"

#include <algorithm>
#include <cctype>

#include "core/render/backend.h"

namespace prism::viewer {
namespace {

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

}  // namespace

std::string why_backend_unavailable(const std::string& spec) {
    BackendSpec parsed = parse_backend_spec(spec);
    if (parsed.api == "cpu-ref") return "";  // the reference renderer always runs
    for (const BackendFactory& factory : registered_backends()) {
        if (factory.name != parsed.api) continue;
        BackendAvailability availability = factory.probe();
        if (!availability.available) return availability.detail;
        if (parsed.device_filter.empty()) return "";
        for (const std::string& device : availability.devices)
            if (lower(device).find(lower(parsed.device_filter)) != std::string::npos) return "";
        return "no " + parsed.api + " device matches '" + parsed.device_filter + "'";
    }
    return "not compiled into this build";
}

}  // namespace prism::viewer
