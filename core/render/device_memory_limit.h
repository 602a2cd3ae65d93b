// PRISM_DEVICE_MEMORY_LIMIT: a byte cap on what a GPU backend may allocate, so tests can exercise the
// out-of-memory path without filling a device. One parser for every backend.
#pragma once

#include <cstddef>
#include <optional>

namespace prism {

// The cap, or nullopt when the variable is unset or empty. Throws prism::Error when it is not a byte count.
std::optional<size_t> device_memory_limit();

}  // namespace prism
