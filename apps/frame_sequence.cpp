#include "apps/frame_sequence.h"

#include <cctype>
#include <charconv>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/util/error.h"

namespace prism::app {
namespace {

bool parse_frame_number(std::string_view text, uint32_t& value) {
    if (text.empty()) return false;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size();
}

// Where the integer field of `pattern` is: [begin, end) and its zero-padded width (0 = none).
struct NumberField {
    size_t begin = std::string::npos, end = 0;
    int width = 0;
};

NumberField find_number_field(const std::string& pattern) {
    NumberField field;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') continue;
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            ++i;
            continue;
        }
        size_t j = i + 1;
        int width = 0;
        while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])))
            width = width * 10 + (pattern[j++] - '0');
        if (j >= pattern.size() || pattern[j] != 'd' || width > 12)
            throw Error("--out '" + pattern + "': '%' must start %d, %0Nd (N up to 12) or %%");
        if (field.begin != std::string::npos) throw Error("--out '" + pattern + "': more than one frame-number field");
        field = NumberField{i, j + 1, width};
        i = j;
    }
    if (field.begin == std::string::npos)
        throw Error("--out '" + pattern + "': a sequence needs a frame-number field in the name, e.g. out_%04d.png");
    return field;
}

}  // namespace

FrameRange parse_frame_range(const std::string& text) {
    FrameRange range;
    size_t dash = text.find('-');
    std::string_view all(text);
    bool ok = dash == std::string::npos ? parse_frame_number(all, range.first) && (range.last = range.first, true)
                                        : parse_frame_number(all.substr(0, dash), range.first) &&
                                              parse_frame_number(all.substr(dash + 1), range.last);
    if (!ok) throw Error("--frames '" + text + "': expected A-B or N (non-negative frame numbers)");
    if (range.last < range.first) throw Error("--frames '" + text + "': the last frame is before the first");
    return range;
}

void check_numbered_output_pattern(const std::string& pattern) { find_number_field(pattern); }

std::string numbered_output_path(const std::string& pattern, uint32_t frame) {
    NumberField field = find_number_field(pattern);
    std::string number = std::to_string(frame);
    if (int(number.size()) < field.width) number.insert(0, size_t(field.width) - number.size(), '0');
    std::string out;
    for (size_t i = 0; i < pattern.size(); ++i) {
        if (i == field.begin) {
            out += number;
            i = field.end - 1;
        } else if (pattern[i] == '%' && i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%';
            ++i;
        } else {
            out += pattern[i];
        }
    }
    return out;
}

Camera turntable_camera(const Camera& camera, uint32_t frame, double seconds, double fps) {
    if (!(seconds > 0.0) || !(fps > 0.0)) return camera;
    // The angle is reduced to one turn in double before the float rotation, so frame N and frame N + turn match.
    double turns = std::fmod(double(frame) / fps / seconds, 1.0);
    float angle = static_cast<float>(turns * 2.0 * 3.14159265358979323846);
    glm::mat4 rotation = glm::rotate(glm::mat4(1.0f), angle, glm::normalize(camera.up));
    Camera moved = camera;
    moved.position = camera.target + glm::vec3(rotation * glm::vec4(camera.position - camera.target, 0.0f));
    return moved;
}

}  // namespace prism::app
