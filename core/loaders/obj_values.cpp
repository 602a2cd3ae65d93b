#include "core/loaders/obj_values.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <span>

#include "core/util/error.h"

namespace prism {
namespace {

enum Kind { kPosition, kUv, kNormal };
constexpr const char* kKindName[] = {"vertex", "texture coordinate", "normal"};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Calls `visit(line_number, words, continued)` for each line, the words split on blanks (a '#' starts a
// comment). A line of more words than fit is handed over in slices, each starting with the keyword;
// `continued` is true for the slices after the first.
template <typename Visit>
void for_each_line(std::string_view text, Visit visit) {
    size_t line_number = 0;
    std::array<std::string_view, 32> words;
    while (!text.empty()) {
        const size_t end = text.find('\n');
        std::string_view line = text.substr(0, end);
        text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
        ++line_number;
        if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        size_t count = 0;
        size_t i = 0;
        bool continued = false;
        while (i < line.size()) {
            while (i < line.size() && is_space(line[i])) ++i;
            const size_t start = i;
            while (i < line.size() && !is_space(line[i])) ++i;
            if (i > start) {
                if (count == words.size()) {
                    visit(line_number, std::span<const std::string_view>(words.data(), count), continued);
                    continued = true;
                    count = 1;
                }
                words[count++] = line.substr(start, i - start);
            }
        }
        if (count > 0) visit(line_number, std::span<const std::string_view>(words.data(), count), continued);
    }
}

// The whole word as a number (a leading '+' allowed), or NaN when it is not one.
double number_or_nan(std::string_view word) {
    if (!word.empty() && word.front() == '+') word.remove_prefix(1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    return error == std::errc() && end == word.data() + word.size() ? value : std::nan("");
}

void check_number(const std::string& file, size_t line, std::string_view keyword, std::string_view word) {
    if (std::isfinite(number_or_nan(word))) return;
    throw file_error(file, line, std::string(keyword) + " value '" + shorten(word, 40) + "' is not a finite number");
}

// Skin weights ("vw vertex joint weight ...", a tinyobjloader extension Prism does not use): tinyobjloader reads the
// vertex with atoi and converts each joint to int, both undefined past int's range (UBSan, fuzz_obj: a joint of
// 1e39000). Every value of the line must be finite and within that range.
void check_skin_weight(const std::string& file, size_t line, std::string_view word) {
    if (std::fabs(number_or_nan(word)) <= double(INT32_MAX)) return;
    throw file_error(
        file, line,
        "skin weight (vw) value '" + shorten(word, 40) + "' is not a number within +-" + std::to_string(INT32_MAX));
}

// One index as written ("-5", "12"): an integer naming an existing element.
void check_index(const std::string& file, size_t line, std::string_view statement, std::string_view written, Kind kind,
                 int64_t defined_above, int64_t defined_in_file) {
    int64_t index = 0;
    const auto [end, error] = std::from_chars(written.data(), written.data() + written.size(), index);
    if (error == std::errc::result_out_of_range && end == written.data() + written.size())
        throw file_error(file, line,
                         std::string(kKindName[kind]) + " index " + shorten(written, 40) + " is out of range (" +
                             std::to_string(defined_in_file) + " in the file)");
    if (error != std::errc() || end != written.data() + written.size())
        throw file_error(file, line,
                         std::string(kKindName[kind]) + " index '" + shorten(written, 40) + "' is not an integer");
    const bool valid =
        index > 0 ? index <= defined_in_file && index <= INT32_MAX : index < 0 && -index <= defined_above;
    if (valid) return;
    if (index == 0)
        throw file_error(file, line, std::string(kKindName[kind]) + " index 0 is invalid (OBJ counts from 1)");
    throw file_error(file, line,
                     std::string(statement) + " references " + kKindName[kind] + " " + std::string(written) +
                         " but there are " + std::to_string(index < 0 ? defined_above : defined_in_file) +
                         (index < 0 ? " above it" : ""));
}

}  // namespace

void check_obj_values(const std::string& file, std::string_view text) {
    std::array<int64_t, 3> in_file{0, 0, 0};
    for_each_line(text, [&](size_t, std::span<const std::string_view> words, bool continued) {
        if (continued) return;
        if (words[0] == "v")
            ++in_file[kPosition];
        else if (words[0] == "vt")
            ++in_file[kUv];
        else if (words[0] == "vn")
            ++in_file[kNormal];
    });
    std::array<int64_t, 3> above{0, 0, 0};
    for_each_line(text, [&](size_t line, std::span<const std::string_view> words, bool continued) {
        const std::string_view keyword = words[0];
        if (keyword == "v" || keyword == "vt" || keyword == "vn") {
            for (size_t i = 1; i < words.size(); ++i) check_number(file, line, keyword, words[i]);
            if (!continued) ++above[keyword == "v" ? kPosition : keyword == "vt" ? kUv : kNormal];
            return;
        }
        if (keyword == "vw") {
            for (size_t i = 1; i < words.size(); ++i) check_skin_weight(file, line, words[i]);
            return;
        }
        if (keyword != "f" && keyword != "l" && keyword != "p") return;
        const std::string_view statement = keyword == "f" ? "face" : keyword == "l" ? "line" : "point";
        for (size_t i = 1; i < words.size(); ++i) {
            // v, v/vt, v//vn, v/vt/vn
            std::string_view corner = words[i];
            for (int kind_slot = 0; kind_slot < 3 && !corner.empty(); ++kind_slot) {
                const size_t slash = corner.find('/');
                const std::string_view written = corner.substr(0, slash);
                const Kind kind = kind_slot == 0 ? kPosition : kind_slot == 1 ? kUv : kNormal;
                if (!written.empty() || kind_slot == 0)
                    check_index(file, line, statement, written, kind, above[kind], in_file[kind]);
                if (slash == std::string_view::npos) break;
                corner = corner.substr(slash + 1);
            }
        }
    });
}

}  // namespace prism
