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

// A value quoted in a message, cut to `max` characters with the full length said ("data:application/octet-...
// (1048597 characters)"), so a megabyte URI does not become a megabyte error line.
std::string shorten(std::string_view text, size_t max = 80);

// A file path quoted in a message: whole up to PATH_MAX, since a path cut short names no file; only a hostile
// megabyte "path" is cut.
inline std::string shorten_path(std::string_view path) { return shorten(path, 4096); }

// A third-party library's error text in Prism's words: its first non-empty line, without nlohmann's
// "[json.exception.parse_error.101] " tags, shortened; `fallback` when nothing is left.
std::string library_message(std::string_view text, std::string_view fallback);

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(one_line(message)) {}
    explicit Error(const char* message) : std::runtime_error(one_line(message)) {}
};

// "<file>: <cause>" or "<file>:<line>: <cause>" — the shape every loader error takes.
inline Error file_error(const std::string& file, const std::string& cause) { return Error(file + ": " + cause); }
inline Error file_error(const std::string& file, size_t line, const std::string& cause) {
    return Error(file + ":" + std::to_string(line) + ": " + cause);
}

}  // namespace prism
