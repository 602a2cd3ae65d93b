// The checks tinyobjloader does not make, run over the OBJ text before it parses: it reads "nan" and "inf" as
// numbers, a malformed number as 0, an index such as 99999999999999999999 or 3.5e9 as whatever its integer
// parser leaves, and reports an index relative to the end (-5) only after resolving it. Here every value is
// judged as written, with its line.
#pragma once

#include <string>
#include <string_view>

namespace prism {

// Throws prism::Error "<file>:<line>: <cause>" for a v/vn/vt value that is not a finite number, or a face, line
// or point index that is not an integer naming an existing vertex, normal or texture coordinate (negative
// indices count back from the last one defined above them; positive ones may name any in the file).
void check_obj_values(const std::string& file, std::string_view text);

}  // namespace prism
