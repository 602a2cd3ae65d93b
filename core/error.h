// One error type for everything the user can cause (bad files, bad options, missing devices).
// The message is the whole one-line report; main() prints it once and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace prism {

// `text` with every control character written as \xNN. Causes quote bytes from the file ("bad element count
// '...'"); a CR, NUL or escape sequence among them would break the one-line report or rewrite the terminal.
std::string one_line(std::string_view text);

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(one_line(message)) {}
    explicit Error(const char* message) : std::runtime_error(one_line(message)) {}
};

// "<file>: <cause>" or "<file>:<line>: <cause>" — the shape every loader error takes.
inline Error file_error(const std::string& file, const std::string& cause) {
    return Error(file + ": " + cause);
}
inline Error file_error(const std::string& file, size_t line, const std::string& cause) {
    return Error(file + ":" + std::to_string(line) + ": " + cause);
}

}  // namespace prism
