// Opening a file named by the user or by a scene: only regular files. A FIFO would block open() or read() for
// ever, a device (/dev/zero, /dev/urandom) never ends, a directory is no file at all; each gets one line at once.
#pragma once

#include <filesystem>
#include <string>

namespace prism {

// Throws prism::Error "<file>: <cause>" unless `path` (after symbolic links) is an existing regular file.
// Never opens the file, so it cannot block.
void require_regular_file(const std::filesystem::path& path);

// The whole file. Opened without blocking and checked on the open descriptor (so a file swapped for a FIFO
// between the check and the open is still refused). Throws prism::Error "<file>: <cause>".
std::string read_input_file(const std::filesystem::path& path);

}  // namespace prism
