// Text files as Windows tools write them: a UTF-8 byte-order mark in front, or UTF-16 with its byte-order mark. The
// OBJ and MTL readers read ASCII keywords from the start of the file, so the first line's keyword was lost (a vertex
// dropped, every later face off by one) or the whole file read as no faces.
#pragma once

#include <string>

namespace prism {

// `bytes` without a leading UTF-8 byte-order mark; UTF-16 (little- or big-endian, with its mark) as UTF-8 (an
// unpaired surrogate becomes U+FFFD; a final odd byte is dropped). Anything else is returned as it is.
std::string utf8_text(std::string bytes);

}  // namespace prism
