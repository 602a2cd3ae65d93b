// Writes a whole output file or nothing: bytes go to "<path>.tmp-<pid>" and are renamed into place, so a failed
// run never leaves a partial file where the user expects a result.
#pragma once

#include <filesystem>
#include <string_view>

namespace prism {

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace prism
