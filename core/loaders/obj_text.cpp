#include "core/loaders/obj_text.h"

#include <array>

namespace prism {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// The text with every backslash-newline (before which only blanks may follow the backslash) replaced by a blank;
// the newlines it swallowed follow the joined line, so the next line keeps its number.
std::string join_continued_lines(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    size_t swallowed = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\\') {
            size_t j = i + 1;
            while (j < text.size() && is_blank(text[j])) ++j;
            if (j < text.size() && text[j] == '\n') {
                out += ' ';
                ++swallowed;
                i = j;
                continue;
            }
        }
        out += c;
        if (c == '\n') out.append(swallowed, '\n'), swallowed = 0;
    }
    out.append(swallowed, '\n');
    return out;
}

// The keyword of a line: its first word.
std::string_view keyword_of(std::string_view line) {
    size_t i = 0;
    while (i < line.size() && is_blank(line[i])) ++i;
    size_t end = i;
    while (end < line.size() && !is_blank(line[end])) ++end;
    return line.substr(i, end - i);
}

bool is_element_statement(std::string_view keyword) { return keyword == "f" || keyword == "l" || keyword == "p"; }

// Calls visit(line, keyword) for each line of `text` (without its newline).
template <typename Visit>
void for_each_line(std::string_view text, Visit visit) {
    for (size_t start = 0; start <= text.size();) {
        const size_t end = std::min(text.find('\n', start), text.size());
        const std::string_view line = text.substr(start, end - start);
        visit(line, keyword_of(line), end < text.size());
        start = end + 1;
    }
}

// Calls visit(corner) for each word after the keyword of an f, l or p line, up to a comment.
template <typename Visit>
void for_each_corner(std::string_view line, std::string_view keyword, Visit visit) {
    const std::string_view body = line.substr(0, line.find('#'));
    size_t i = body.find(keyword) + keyword.size();
    while (i < body.size()) {
        while (i < body.size() && is_blank(body[i])) ++i;
        size_t end = i;
        while (end < body.size() && !is_blank(body[end])) ++end;
        if (end > i) visit(body.substr(i, end - i));
        i = end;
    }
}

// A corner "v", "v/vt", "v//vn" or "v/vt/vn" split into its three fields (empty where not written).
struct Corner {
    std::array<std::string_view, 3> field{};
    bool empty_at_end = false;  // "7//", "7/3/"
};

Corner split_corner(std::string_view text) {
    Corner corner;
    corner.empty_at_end = !text.empty() && text.back() == '/';
    for (size_t k = 0; k < 3; ++k) {
        const size_t slash = text.find('/');
        corner.field[k] = text.substr(0, slash);
        if (slash == std::string_view::npos) break;
        text.remove_prefix(slash + 1);
    }
    return corner;
}

// The corner as tinyobjloader reads it: without the fields dropped, and without empty fields at its end.
std::string join_corner(const Corner& corner, bool keep_uv, bool keep_normal) {
    const std::string_view uv = keep_uv ? corner.field[1] : std::string_view();
    const std::string_view normal = keep_normal ? corner.field[2] : std::string_view();
    std::string out(corner.field[0]);
    if (!normal.empty())
        out.append("/").append(uv).append("/").append(normal);
    else if (!uv.empty())
        out.append("/").append(uv);
    return out;
}

}  // namespace

ObjText normalize_obj_text(const std::string& file, std::string_view input) {
    ObjText result;
    std::string joined = join_continued_lines(input);

    bool has_uv = false, has_normal = false, names_uv = false, names_normal = false, empty_at_end = false;
    for_each_line(joined, [&](std::string_view line, std::string_view keyword, bool) {
        has_uv |= keyword == "vt";
        has_normal |= keyword == "vn";
        if (!is_element_statement(keyword)) return;
        for_each_corner(line, keyword, [&](std::string_view text) {
            const Corner corner = split_corner(text);
            names_uv |= !corner.field[1].empty();
            names_normal |= !corner.field[2].empty();
            empty_at_end |= corner.empty_at_end;
        });
    });
    const bool drop_uv = names_uv && !has_uv, drop_normal = names_normal && !has_normal;
    if (!empty_at_end && !drop_uv && !drop_normal) {
        result.text = std::move(joined);
        return result;
    }

    result.text.reserve(joined.size());
    for_each_line(joined, [&](std::string_view line, std::string_view keyword, bool newline) {
        if (is_element_statement(keyword)) {
            result.text.append(keyword);
            for_each_corner(line, keyword, [&](std::string_view text) {
                result.text.append(" ").append(join_corner(split_corner(text), has_uv, has_normal));
            });
        } else {
            result.text.append(line);
        }
        if (newline) result.text += '\n';
    });
    if (drop_uv)
        result.warnings.push_back(file + ": faces name texture coordinates but the file has no vt line; ignored");
    if (drop_normal) result.warnings.push_back(file + ": faces name normals but the file has no vn line; ignored");
    return result;
}

}  // namespace prism
