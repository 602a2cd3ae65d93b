// One error type for everything the user can cause (bad files, bad options, missing devices).
// The message is the whole one-line report; main() prints it once and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace prism {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// "<file>: <cause>" or "<file>:<line>: <cause>" — the shape every loader error takes.
inline Error file_error(const std::string& file, const std::string& cause) {
    return Error(file + ": " + cause);
}
inline Error file_error(const std::string& file, size_t line, const std::string& cause) {
    return Error(file + ":" + std::to_string(line) + ": " + cause);
}

}  // namespace prism
