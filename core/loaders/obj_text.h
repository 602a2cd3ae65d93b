// OBJ text that tinyobjloader cannot read but other tools do, rewritten before it parses (each line stays on its
// line number, so errors still point into the file as written):
// - a line ending in a backslash goes on in the next one (the OBJ format's long lines): the two are joined;
// - a corner with empty fields at its end ("7//", "7/3/", written by some exporters) loses them;
// - texture coordinate or normal indices in a file without any vt or vn line (an exporter's placeholders) are
//   dropped, with a warning, so the faces load with their positions.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace prism {

struct ObjText {
    std::string text;
    std::vector<std::string> warnings;  // "<file>: ..."
};

ObjText normalize_obj_text(const std::string& file, std::string_view text);

}  // namespace prism
