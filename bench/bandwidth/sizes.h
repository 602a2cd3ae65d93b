// Transfer sizes on the command line ("4K", "16M,256M", "1G") and in tables.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace prism::bandwidth {

// 4 KiB to 1 GiB in powers of 4: the default sweep.
std::vector<size_t> default_sizes();
// Comma-separated sizes: a number of bytes with an optional binary suffix K, M or G (KiB, MiB, GiB; "KiB",
// "MB" etc. are accepted too). Each must be a multiple of 16 bytes (the kernel copies 16-byte elements).
// Throws prism::Error("--sizes: <cause>") on anything else.
std::vector<size_t> parse_sizes(const std::string& text);
// "4K", "1M", "1.5M", "1G", "100B".
std::string format_size(size_t bytes);

}  // namespace prism::bandwidth
