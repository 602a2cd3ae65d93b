// The device part of a backend name ("cuda:1", "opencl:nvidia"): every GPU backend reads a number as the device's
// place in its own list (the order `prism info` prints and `<api>:all` uses) and anything else as a name to match.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace prism {

// The index a filter of digits names; nullopt for a name. A number too large for size_t is an index past every
// list, so the backend reports "no device N" like any other index out of range.
std::optional<size_t> device_index(const std::string& filter);

// `text` in lower case (ASCII): device names are matched without regard to case.
std::string lowercase(std::string text);
// Whether `name` contains `filter`, ignoring case: how every API matches a device name to a filter.
bool name_matches(const std::string& name, const std::string& filter);

}  // namespace prism
