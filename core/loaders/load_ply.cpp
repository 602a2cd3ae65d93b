// A PLY reader written for this project (Debian packages none). The whole file (inflated when gzip) is read into
// memory once; the ASCII body is tokenised in place with std::from_chars, the binary body with memcpy, so the
// 871k-triangle dragon loads in well under a second. Elements the tracer does not need are skipped in every format.
#include "core/loaders/load_ply.h"

#include "core/scene/corner_uvs.h"
#include "core/scene/mesh_normals.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <zlib.h>

#include "core/util/error.h"
#include "core/util/input_file.h"
#include "core/util/load_progress.h"
#include "core/util/non_copyable.h"

namespace prism {
namespace {

// ---- reading the file ------------------------------------------------------------------------------------------

// The inflated bytes of a gzip file, at most `limit(inflated so far)` of them: the callback sees the inflated
// prefix and answers how much the whole may take (once the header is in, what its element counts need).
// The inflater's state, released however reading ends: the limit callback throws when the header is malformed
// (fuzz_ply found the leak when it did not).
class Inflater : private NonCopyable {
public:
    explicit Inflater(const std::filesystem::path& path) {
        if (inflateInit2(&stream_, 15 + 32) != Z_OK) throw file_error(path.string(), "cannot start zlib");
    }
    ~Inflater() { inflateEnd(&stream_); }
    z_stream& stream() { return stream_; }

private:
    z_stream stream_{};
};

// Progress (core/util/load_progress.h): the element loops report every kElementsPerReport elements of a body with at
// least kElementsWorthReporting (a small file loads at once, and one that fails leaves only its error line); a
// gzip stream of kGzipBytesWorthReporting or more reports its inflation, which takes about kInflateShare of the
// load (the dragon's).
constexpr uint64_t kElementsPerReport = 1u << 16;
constexpr uint64_t kElementsWorthReporting = 1u << 20;
constexpr size_t kGzipBytesWorthReporting = size_t(4) << 20;
constexpr double kInflateShare = 0.4;

template <typename Limit>
std::string read_gzip_file(const std::filesystem::path& path, const std::string& compressed, Limit limit) {
    Inflater inflater(path);
    z_stream& stream = inflater.stream();
    std::string bytes;
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    size_t input_left = compressed.size();
    int status = Z_OK;
    for (;;) {
        const size_t allowed = limit(std::string_view(bytes));
        if (bytes.size() > allowed) {
            throw file_error(path.string(), "gzip stream inflates past the " + std::to_string(allowed) +
                                                " bytes its PLY header's element counts can need");
        }
        const size_t used = bytes.size();
        const size_t step = std::min<size_t>(std::max<size_t>(used, 1u << 16), 1u << 26);
        bytes.resize(used + step);
        stream.next_out = reinterpret_cast<Bytef*>(bytes.data() + used);
        stream.avail_out = static_cast<uInt>(step);
        if (stream.avail_in == 0) {
            const size_t feed = std::min<size_t>(input_left, 1u << 30);
            stream.avail_in = static_cast<uInt>(feed);
            input_left -= feed;
        }
        status = inflate(&stream, Z_NO_FLUSH);
        bytes.resize(used + (step - stream.avail_out));
        if (compressed.size() >= kGzipBytesWorthReporting)
            report_load_progress(double(compressed.size() - input_left - stream.avail_in) / double(compressed.size()));
        if (status == Z_STREAM_END) {
            // Concatenated gzip members (gzip a b > c.gz) are one file to gzip's tools.
            if (stream.avail_in == 0 && input_left == 0) break;
            if (inflateReset(&stream) != Z_OK) break;
            continue;
        }
        if (status == Z_BUF_ERROR && stream.avail_in == 0 && input_left == 0) {
            throw file_error(path.string(), "corrupt gzip stream (unexpected end of file)");
        }
        if (status != Z_OK && status != Z_BUF_ERROR) {
            const std::string reason = stream.msg ? stream.msg : "error " + std::to_string(status);
            throw file_error(path.string(), "corrupt gzip stream (" + reason + ")");
        }
    }
    if (bytes.size() > limit(std::string_view(bytes)))
        throw file_error(path.string(), "gzip stream inflates past what its PLY header's element counts can need");
    return bytes;
}

// By the magic bytes alone: a ".gz" that is not gzip is read as it is, as zlib's gzread would.
bool looks_gzipped(std::string_view bytes) {
    return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// ---- the header ------------------------------------------------------------------------------------------------

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_scalar(std::string_view name, Scalar& type) {
    static constexpr std::pair<std::string_view, Scalar> names[] = {
        {"char", Scalar::Int8},      {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
        {"uint8", Scalar::UInt8},    {"short", Scalar::Int16},     {"int16", Scalar::Int16},
        {"ushort", Scalar::UInt16},  {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
        {"int32", Scalar::Int32},    {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
        {"float", Scalar::Float32},  {"float32", Scalar::Float32}, {"double", Scalar::Float64},
        {"float64", Scalar::Float64}};
    for (const auto& [spelling, value] : names)
        if (spelling == name) {
            type = value;
            return true;
        }
    return false;
}

size_t scalar_size(Scalar type) {
    switch (type) {
        case Scalar::Int8:
        case Scalar::UInt8: return 1;
        case Scalar::Int16:
        case Scalar::UInt16: return 2;
        case Scalar::Int32:
        case Scalar::UInt32:
        case Scalar::Float32: return 4;
        case Scalar::Float64: return 8;
    }
    return 0;
}

bool is_integer(Scalar type) { return type != Scalar::Float32 && type != Scalar::Float64; }

// What an 8/16/32-bit colour channel's largest value means (1.0); floats are taken as given.
float colour_scale(Scalar type) {
    switch (type) {
        case Scalar::Int8: return 1.0f / 127.0f;
        case Scalar::UInt8: return 1.0f / 255.0f;
        case Scalar::Int16: return 1.0f / 32767.0f;
        case Scalar::UInt16: return 1.0f / 65535.0f;
        case Scalar::Int32: return 1.0f / 2147483647.0f;
        case Scalar::UInt32: return 1.0f / 4294967295.0f;
        default: return 1.0f;
    }
}

struct Property {
    std::string name;
    bool is_list = false;
    Scalar count_type = Scalar::UInt8;  // lists only
    Scalar type = Scalar::Float32;      // the value type (of the list's entries for lists)
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::vector<std::string> texture_files;  // "comment TextureFile <name>" lines (MeshLab), in order
    size_t body_offset = 0;                  // first byte after the end_header line
    char line_end = '\n';                    // '\r' in files whose lines end in a CR alone
};

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

bool is_texture_file_keyword(std::string_view word) {
    constexpr std::string_view keyword = "texturefile";
    return word.size() == keyword.size() && std::equal(word.begin(), word.end(), keyword.begin(), [](char a, char b) {
               return std::tolower(static_cast<unsigned char>(a)) == b;
           });
}

Header parse_header(const std::string& file, std::string_view bytes) {
    Header header;
    bool have_format = false;
    size_t offset = 0;
    size_t line_number = 0;
    // Lines end in LF or CR LF, or in a CR alone where the file's first line does (Rhinoceros wrote such files:
    // Draco's testdata/Box.ply).
    const char line_end = bytes.starts_with("ply\r") && !bytes.starts_with("ply\r\n") ? '\r' : '\n';
    header.line_end = line_end;
    for (;;) {
        const size_t newline = bytes.find(line_end, offset);
        if (newline == std::string_view::npos) {
            if (line_number == 0) throw file_error(file, "not a PLY file (no 'ply' line)");
            throw file_error(file, "PLY header has no end_header line (not a PLY file, or truncated)");
        }
        std::string_view line = bytes.substr(offset, newline - offset);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        offset = newline + 1;
        ++line_number;
        if (line_number == 1) {
            if (line != "ply") throw file_error(file, "not a PLY file (no 'ply' line)");
            continue;
        }
        const std::vector<std::string_view> words = split_words(line);
        if (words.empty()) continue;
        const std::string_view keyword = words[0];
        auto fail = [&](const std::string& cause) { return file_error(file, line_number, cause); };
        if (keyword == "comment" && words.size() >= 3 && is_texture_file_keyword(words[1])) {
            // The name is the rest of the line: MeshLab writes names with spaces ("fuze uv.jpg") as they are.
            std::string_view name = line.substr(static_cast<size_t>(words[1].data() + words[1].size() - line.data()));
            while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
            while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
            header.texture_files.emplace_back(name);
            continue;
        }
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") {
            if (!have_format) throw fail("PLY header has no format line");
            header.body_offset = offset;
            return header;
        }
        if (keyword == "format") {
            if (words.size() != 3) throw fail("malformed format line");
            if (words[2] != "1.0") throw fail("unsupported PLY version '" + std::string(words[2]) + "'");
            if (words[1] == "ascii")
                header.format = Format::Ascii;
            else if (words[1] == "binary_little_endian")
                header.format = Format::BinaryLittleEndian;
            else if (words[1] == "binary_big_endian")
                header.format = Format::BinaryBigEndian;
            else
                throw fail("unsupported PLY format '" + std::string(words[1]) + "'");
            have_format = true;
        } else if (keyword == "element") {
            if (words.size() != 3) throw fail("malformed element line");
            Element element;
            element.name = std::string(words[1]);
            auto [end, error] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
            if (error != std::errc() || end != words[2].data() + words[2].size())
                throw fail("bad element count '" + std::string(words[2]) + "'");
            header.elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (header.elements.empty()) throw fail("property before any element");
            Property property;
            if (words.size() == 5 && words[1] == "list") {
                property.is_list = true;
                if (!parse_scalar(words[2], property.count_type) || !parse_scalar(words[3], property.type))
                    throw fail("unknown property type in '" + std::string(line) + "'");
                if (!is_integer(property.count_type)) throw fail("list count type must be an integer type");
                property.name = std::string(words[4]);
            } else if (words.size() == 3) {
                if (!parse_scalar(words[1], property.type))
                    throw fail("unknown property type '" + std::string(words[1]) + "'");
                property.name = std::string(words[2]);
            } else {
                throw fail("malformed property line");
            }
            header.elements.back().properties.push_back(std::move(property));
        } else if (header.elements.empty()) {
            // Before the first element only the format matters; Blender 2.4x wrote "Created by Blender3D ..." here
            // without "comment" (assimp's Wuson.ply). Such a line is read as the comment it was meant to be.
            continue;
        } else {
            throw fail("unknown PLY header keyword '" + std::string(keyword) + "'");
        }
    }
}

// ---- the body: one source type per encoding, the element readers are templates over them ---------------------

// Thrown by the sources; the element loop turns it into the user's message (it knows which element failed).
struct ParseFailure {
    bool truncated = false;
    const char* position = nullptr;
    std::string cause;
};

class AsciiSource {
public:
    AsciiSource(const char* begin, const char* end) : current_(begin), end_(end) {}

    float read_float(Scalar) {
        auto [begin, end] = next_token();
        if (*begin == '+') ++begin;
        float value = 0.0f;
        auto [stop, error] = std::from_chars(begin, end, value);
        // Out-of-range values (1e999) become infinities; validate_scene reports non-finite positions by vertex.
        if (error == std::errc::result_out_of_range) return *begin == '-' ? -INFINITY : INFINITY;
        if (error != std::errc() || stop != end) bad_token(begin, end, "a number");
        return value;
    }
    int64_t read_integer(Scalar) {
        auto [begin, end] = next_token();
        if (*begin == '+') ++begin;
        int64_t value = 0;
        auto [stop, error] = std::from_chars(begin, end, value);
        if (error != std::errc() || stop != end) bad_token(begin, end, "an integer");
        return value;
    }
    void skip(Scalar) { next_token(); }
    const char* position() const { return current_; }
    // Where the next value starts (after the separating white space), for messages that name its line.
    const char* next_value() {
        skip_separator();
        return current_;
    }
    size_t remaining() const { return static_cast<size_t>(end_ - current_); }
    // One record per line, as every writer puts them (blank lines between records are passed over). Values after
    // the last property the header declares (VCGlib wrote a face's colour as ten values where its header declares
    // four) would otherwise be read as the next record's: they are skipped to the line's end and counted, so the
    // file loads with a warning; a line with too few values is an error on that line, not a misread of the next.
    void end_record() {
        while (current_ != end_ && is_blank(*current_)) ++current_;
        if (current_ != end_ && !is_line_end(*current_)) {
            ++records_with_extra_values_;
            while (current_ != end_ && !is_line_end(*current_)) ++current_;
        }
        at_record_start_ = true;
    }
    // How many records since the last call had values beyond the header's properties.
    uint64_t take_records_with_extra_values() { return std::exchange(records_with_extra_values_, 0); }

private:
    static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }
    static bool is_line_end(char c) { return c == '\n' || c == '\r'; }

    // Before a record's first value: any white space and line ends; inside a record: blanks only.
    void skip_separator() {
        while (current_ != end_ && (is_blank(*current_) || (at_record_start_ && is_line_end(*current_)))) ++current_;
    }
    std::pair<const char*, const char*> next_token() {
        skip_separator();
        if (current_ == end_) throw ParseFailure{true, current_, {}};
        if (is_line_end(*current_))
            throw ParseFailure{false, current_, "line ends before the values its header declares"};
        at_record_start_ = false;
        const char* begin = current_;
        while (current_ != end_ && !is_blank(*current_) && !is_line_end(*current_)) ++current_;
        return {begin, current_};
    }
    [[noreturn]] void bad_token(const char* begin, const char* end, const char* expected) {
        std::string token(begin, std::min<size_t>(end - begin, 40));
        throw ParseFailure{false, begin, std::string("expected ") + expected + ", found '" + token + "'"};
    }

    const char* current_;
    const char* end_;
    bool at_record_start_ = true;
    uint64_t records_with_extra_values_ = 0;
};

template <bool SwapBytes>
class BinarySource {
public:
    BinarySource(const char* begin, const char* end) : current_(begin), end_(end) {}

    float read_float(Scalar type) {
        switch (type) {
            case Scalar::Int8: return static_cast<float>(read<int8_t>());
            case Scalar::UInt8: return static_cast<float>(read<uint8_t>());
            case Scalar::Int16: return static_cast<float>(read<int16_t>());
            case Scalar::UInt16: return static_cast<float>(read<uint16_t>());
            case Scalar::Int32: return static_cast<float>(read<int32_t>());
            case Scalar::UInt32: return static_cast<float>(read<uint32_t>());
            case Scalar::Float32: return read<float>();
            case Scalar::Float64: return static_cast<float>(read<double>());
        }
        return 0.0f;
    }
    int64_t read_integer(Scalar type) {
        switch (type) {
            case Scalar::Int8: return read<int8_t>();
            case Scalar::UInt8: return read<uint8_t>();
            case Scalar::Int16: return read<int16_t>();
            case Scalar::UInt16: return read<uint16_t>();
            case Scalar::Int32: return read<int32_t>();
            case Scalar::UInt32: return read<uint32_t>();
            default: break;  // the header admits only integer types where integers are read
        }
        return 0;
    }
    void skip(Scalar type) { skip_bytes(scalar_size(type)); }
    const char* next_value() const { return current_; }
    void skip_bytes(size_t count) {
        if (static_cast<size_t>(end_ - current_) < count) throw ParseFailure{true, current_, {}};
        current_ += count;
    }
    const char* position() const { return current_; }
    size_t remaining() const { return static_cast<size_t>(end_ - current_); }
    // A binary record is exactly its properties' bytes.
    void end_record() {}
    uint64_t take_records_with_extra_values() { return 0; }

private:
    template <typename T>
    T read() {
        if (static_cast<size_t>(end_ - current_) < sizeof(T)) throw ParseFailure{true, current_, {}};
        std::array<char, sizeof(T)> raw;
        std::memcpy(raw.data(), current_, sizeof(T));
        current_ += sizeof(T);
        if constexpr (SwapBytes) std::reverse(raw.begin(), raw.end());
        return std::bit_cast<T>(raw);
    }

    const char* current_;
    const char* end_;
};

template <typename Source>
void skip_property(Source& source, const Property& property) {
    if (!property.is_list) {
        source.skip(property.type);
        return;
    }
    const int64_t count = source.read_integer(property.count_type);
    if (count < 0) throw ParseFailure{false, source.position(), "negative list length " + std::to_string(count)};
    for (int64_t i = 0; i < count; ++i) source.skip(property.type);
}

template <typename Source>
void skip_element(Source& source, const Element& element, uint64_t& index) {
    // An element without properties has nothing to read, however many it declares (counting to 2^32 - 1 took a
    // sanitizer build 19 s).
    if (element.properties.empty()) {
        index = element.count;
        return;
    }
    for (index = 0; index < element.count; ++index) {
        for (const Property& property : element.properties) skip_property(source, property);
        source.end_record();
    }
}

template <bool SwapBytes>
void skip_element(BinarySource<SwapBytes>& source, const Element& element, uint64_t& index) {
    const bool fixed_size =
        std::none_of(element.properties.begin(), element.properties.end(), [](const Property& p) { return p.is_list; });
    if (!fixed_size) {
        for (index = 0; index < element.count; ++index)
            for (const Property& property : element.properties) skip_property(source, property);
        return;
    }
    // Fixed-size records: jump over them at once (and say which record the file ends in if it is short).
    size_t record = 0;
    for (const Property& property : element.properties) record += scalar_size(property.type);
    if (record == 0) return;
    const uint64_t available = source.remaining() / record;
    if (available < element.count) {
        index = available;
        throw ParseFailure{true, source.position(), {}};
    }
    source.skip_bytes(static_cast<size_t>(element.count * record));
    index = element.count;
}

// Where each vertex property goes. Indices into a small per-vertex scratch array.
enum Slot { X, Y, Z, NX, NY, NZ, Red, Green, Blue, Alpha, U, V, SlotCount, Ignored = SlotCount };

Slot slot_for(const std::string& name) {
    static const std::pair<const char*, Slot> names[] = {{"x", X},
                                                         {"y", Y},
                                                         {"z", Z},
                                                         {"nx", NX},
                                                         {"ny", NY},
                                                         {"nz", NZ},
                                                         {"red", Red},
                                                         {"green", Green},
                                                         {"blue", Blue},
                                                         {"alpha", Alpha},
                                                         {"diffuse_red", Red},
                                                         {"diffuse_green", Green},
                                                         {"diffuse_blue", Blue},
                                                         {"u", U},
                                                         {"v", V},
                                                         {"s", U},
                                                         {"t", V},
                                                         {"texture_u", U},
                                                         {"texture_v", V},
                                                         {"texture_s", U},
                                                         {"texture_t", V}};
    for (const auto& [spelling, slot] : names)
        if (name == spelling) return slot;
    return Ignored;
}

struct VertexLayout {
    std::vector<Slot> slots;    // per property
    std::vector<float> scales;  // per property: colour normalisation, else 1
    bool has_normals = false, has_colors = false, has_alpha = false, has_uvs = false;
};

VertexLayout vertex_layout(const std::string& file, const Element& element) {
    VertexLayout layout;
    std::array<bool, SlotCount> present{};
    for (const Property& property : element.properties) {
        Slot slot = property.is_list ? Ignored : slot_for(property.name);
        if (slot != Ignored && present[slot]) slot = Ignored;  // a repeated name: the first one wins
        if (slot != Ignored) present[slot] = true;
        layout.slots.push_back(slot);
        const bool colour = slot == Red || slot == Green || slot == Blue || slot == Alpha;
        layout.scales.push_back(colour ? colour_scale(property.type) : 1.0f);
    }
    for (Slot axis : {X, Y, Z})
        if (!present[axis]) throw file_error(file, std::string("vertex element has no '") + "xyz"[axis] + "' property");
    layout.has_normals = present[NX] && present[NY] && present[NZ];
    layout.has_colors = present[Red] && present[Green] && present[Blue];
    layout.has_alpha = present[Alpha];
    layout.has_uvs = present[U] && present[V];
    return layout;
}

// An upper bound on how many records can still be in the file, so a lying header cannot make us reserve gigabytes.
size_t reservable(uint64_t count, size_t remaining_bytes) {
    return static_cast<size_t>(std::min<uint64_t>(count, remaining_bytes / 2 + 1));
}

template <typename Source>
void read_vertices(Source& source, const Element& element, const VertexLayout& layout, Mesh& mesh, uint64_t& index,
                   uint64_t report_every) {
    const size_t capacity = reservable(element.count, source.remaining());
    mesh.positions.reserve(capacity);
    if (layout.has_normals) mesh.normals.reserve(capacity);
    if (layout.has_colors) mesh.colors.reserve(capacity);
    if (layout.has_uvs) mesh.uv0.reserve(capacity);
    std::array<float, SlotCount + 1> values{};
    values[Alpha] = 1.0f;
    const size_t property_count = element.properties.size();
    for (index = 0; index < element.count; ++index) {
        if (index % report_every == 0 && index > 0) report_load_progress(double(index) / double(element.count));
        for (size_t p = 0; p < property_count; ++p) {
            const Property& property = element.properties[p];
            if (property.is_list)
                skip_property(source, property);
            else
                values[layout.slots[p]] = source.read_float(property.type) * layout.scales[p];
        }
        source.end_record();
        mesh.positions.emplace_back(values[X], values[Y], values[Z]);
        if (layout.has_normals) mesh.normals.emplace_back(values[NX], values[NY], values[NZ]);
        if (layout.has_colors) mesh.colors.emplace_back(values[Red], values[Green], values[Blue], values[Alpha]);
        // PLY's v (t) grows upward, as OBJ's and OpenGL's; meshes keep glTF's, which grows downward.
        if (layout.has_uvs) mesh.uv0.emplace_back(values[U], 1.0f - values[V]);
    }
}

// What the face element carries besides its index list, as MeshLab writes textured meshes: texture coordinates
// per corner ("texcoord", a list of 2 per corner) and the texture each face uses ("texnumber", an index into the
// header's "comment TextureFile" names).
struct FaceLayout {
    size_t indices = 0;
    size_t texcoords = SIZE_MAX;  // SIZE_MAX: none
    size_t texnumber = SIZE_MAX;  // SIZE_MAX: none, or the header names no texture file
    size_t texture_files = 0;     // how many the header names
};

struct FaceResult {
    int64_t largest_index = -1;
    uint64_t face_with_largest = 0;
    std::vector<glm::vec2> corner_uvs;  // 3 per triangle when the faces carry texcoord lists
};

template <typename Source>
void read_faces(Source& source, const Element& element, const FaceLayout& layout, Mesh& mesh, FaceResult& result,
                uint64_t& index, uint64_t report_every) {
    const size_t reserve = reservable(element.count, source.remaining());
    mesh.triangles.reserve(mesh.triangles.size() + reserve);
    mesh.triangle_materials.reserve(mesh.triangles.size() + reserve);
    const Property& indices = element.properties[layout.indices];
    std::vector<uint32_t> polygon;
    std::vector<glm::vec2> uvs;
    for (index = 0; index < element.count; ++index) {
        if (index % report_every == 0 && index > 0) report_load_progress(double(index) / double(element.count));
        polygon.clear();
        uvs.clear();
        uint32_t texture = 0;
        const char* face_start = source.next_value();
        for (size_t p = 0; p < element.properties.size(); ++p) {
            const Property& property = element.properties[p];
            if (p == layout.texcoords) {
                const int64_t count = source.read_integer(property.count_type);
                if (count < 0 || count % 2 != 0 || count > 2 * 255)
                    throw ParseFailure{false, face_start, "has " + std::to_string(count) + " texcoord values"};
                for (int64_t i = 0; i < count; i += 2) {
                    const float u = source.read_float(property.type);
                    uvs.emplace_back(u, 1.0f - source.read_float(property.type));  // v flipped as read_vertices
                }
                continue;
            }
            if (p == layout.texnumber) {
                const int64_t number = source.read_integer(property.type);
                if (number < 0 || static_cast<uint64_t>(number) >= layout.texture_files)
                    throw ParseFailure{false, face_start,
                                       "has texnumber " + std::to_string(number) + " but the header names " +
                                           std::to_string(layout.texture_files) + " texture files"};
                texture = static_cast<uint32_t>(number);
                continue;
            }
            if (p != layout.indices) {
                skip_property(source, property);
                continue;
            }
            const char* list_start = source.next_value();
            const int64_t count = source.read_integer(indices.count_type);
            if (count < 3)
                throw ParseFailure{false, list_start,
                                   "has " + std::to_string(count) + " vertices (a polygon needs at least 3)"};
            for (int64_t i = 0; i < count; ++i) {
                const char* value_start = source.next_value();
                const int64_t vertex = source.read_integer(indices.type);
                if (vertex < 0 || vertex > static_cast<int64_t>(UINT32_MAX))
                    throw ParseFailure{false, value_start, "has vertex index " + std::to_string(vertex)};
                if (vertex > result.largest_index) {
                    result.largest_index = vertex;
                    result.face_with_largest = index;
                }
                polygon.push_back(static_cast<uint32_t>(vertex));
            }
        }
        source.end_record();
        const bool textured = layout.texcoords != SIZE_MAX;
        // An empty list is a face without coordinates (they read as 0, 0); any other count must match the corners.
        if (textured && !uvs.empty() && uvs.size() != polygon.size())
            throw ParseFailure{false, face_start,
                               "has " + std::to_string(2 * uvs.size()) + " texcoord values for " +
                                   std::to_string(polygon.size()) + " corners"};
        if (textured && uvs.empty()) uvs.assign(polygon.size(), glm::vec2(0.0f));
        // Fan triangulation: exact for the convex quads and pentagons scanners and modellers write.
        for (size_t i = 1; i + 1 < polygon.size(); ++i) {
            mesh.triangles.emplace_back(polygon[0], polygon[i], polygon[i + 1]);
            mesh.triangle_materials.push_back(texture);
            if (textured) result.corner_uvs.insert(result.corner_uvs.end(), {uvs[0], uvs[i], uvs[i + 1]});
        }
    }
}

size_t line_of(std::string_view bytes, const char* position, char line_end) {
    const size_t offset = std::min<size_t>(static_cast<size_t>(position - bytes.data()), bytes.size());
    return 1 + static_cast<size_t>(std::count(bytes.data(), bytes.data() + offset, line_end));
}

// What a body with the header's element counts can take at most: every ASCII value in 32 characters (a double
// printed in full takes 24), every list at most 255 entries long (the most a uchar count, the usual type, says).
// A gzip file inflating past this plus a margin is a bomb, not a mesh; it is stopped while it inflates.
constexpr size_t kMaxHeaderBytes = size_t(1) << 20;
constexpr size_t kInflationMargin = size_t(1) << 20;

size_t saturating_add(size_t a, size_t b) { return a > SIZE_MAX - b ? SIZE_MAX : a + b; }
size_t saturating_multiply(size_t a, size_t b) {
    size_t product;
    return __builtin_mul_overflow(a, b, &product) ? SIZE_MAX : product;
}

size_t largest_body(const Header& header) {
    const bool ascii = header.format == Format::Ascii;
    constexpr size_t kAsciiValueBytes = 32, kLongestList = 255;
    size_t total = header.body_offset;
    for (const Element& element : header.elements) {
        size_t record = ascii ? 2 : 0;  // the line end
        for (const Property& property : element.properties) {
            const size_t value = ascii ? kAsciiValueBytes : scalar_size(property.type);
            if (!property.is_list) {
                record += value;
                continue;
            }
            const size_t count_bytes = ascii ? kAsciiValueBytes : scalar_size(property.count_type);
            record += count_bytes + kLongestList * value;
        }
        total = saturating_add(total, saturating_multiply(static_cast<size_t>(element.count), record));
    }
    return total;
}

template <typename Source>
Mesh read_body(const std::string& file, std::string_view bytes, const Header& header, Source source,
               std::vector<std::string>& warnings, std::vector<glm::vec2>& corner_uvs) {
    const Element* vertices = nullptr;
    const Element* faces = nullptr;
    for (const Element& element : header.elements) {
        if (element.name == "vertex" && !vertices) vertices = &element;
        if (element.name == "face" && !faces) faces = &element;
    }
    if (!vertices) throw file_error(file, "PLY file has no vertex element");
    if (!faces) throw file_error(file, "PLY file has no face element (point clouds are not supported)");
    const VertexLayout layout = vertex_layout(file, *vertices);
    const auto list = std::find_if(faces->properties.begin(), faces->properties.end(), [](const Property& p) {
        return p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
    });
    if (list == faces->properties.end()) throw file_error(file, "face element has no 'vertex_indices' list property");
    if (!is_integer(list->type)) throw file_error(file, "face vertex indices must have an integer type");
    FaceLayout face_layout;
    face_layout.indices = static_cast<size_t>(list - faces->properties.begin());
    face_layout.texture_files = header.texture_files.size();
    for (size_t p = 0; p < faces->properties.size(); ++p) {
        const Property& property = faces->properties[p];
        if (property.name == "texcoord" && property.is_list && !is_integer(property.type) &&
            face_layout.texcoords == SIZE_MAX)
            face_layout.texcoords = p;
        if (property.name == "texnumber" && !property.is_list && is_integer(property.type) &&
            !header.texture_files.empty() && face_layout.texnumber == SIZE_MAX)
            face_layout.texnumber = p;
    }

    Mesh mesh;
    FaceResult faces_read;
    // Each element's share of the progress: its part of the header's element count.
    double elements = 0.0, elements_before = 0.0;
    for (const Element& element : header.elements) elements += double(element.count);
    const uint64_t report_every = elements >= double(kElementsWorthReporting) ? kElementsPerReport : UINT64_MAX;
    for (const Element& element : header.elements) {
        uint64_t index = 0;
        LoadProgressShare share(elements_before / std::max(elements, 1.0),
                                (elements_before + double(element.count)) / std::max(elements, 1.0));
        elements_before += double(element.count);
        try {
            if (&element == vertices)
                read_vertices(source, element, layout, mesh, index, report_every);
            else if (&element == faces)
                read_faces(source, element, face_layout, mesh, faces_read, index, report_every);
            else
                skip_element(source, element, index);
        } catch (const ParseFailure& failure) {
            const std::string where = element.name + " " + std::to_string(index);
            if (failure.truncated)
                throw file_error(file, "truncated: " + where + " of " + std::to_string(element.count));
            if (header.format == Format::Ascii)
                throw file_error(file, line_of(bytes, failure.position, header.line_end), where + " " + failure.cause);
            throw file_error(
                file, where + " " + failure.cause + " (byte " + std::to_string(failure.position - bytes.data()) + ")");
        }
        if (const uint64_t extra = source.take_records_with_extra_values(); extra > 0)
            warnings.push_back(file + ": " + std::to_string(extra) + " of " + std::to_string(element.count) + " " +
                               element.name + " lines carry more values than the header declares (ignored)");
    }
    if (faces_read.largest_index >= static_cast<int64_t>(mesh.positions.size()))
        throw file_error(file, "face " + std::to_string(faces_read.face_with_largest) + " references vertex " +
                                   std::to_string(faces_read.largest_index) + " but there are " +
                                   std::to_string(mesh.positions.size()) + " vertices");
    if (mesh.triangles.empty()) throw file_error(file, "PLY file has no faces");
    corner_uvs = std::move(faces_read.corner_uvs);
    return mesh;
}

}  // namespace

Mesh load_ply(const std::filesystem::path& path, PlyDetails* details) {
    const std::string file = path.string();
    std::string bytes = read_input_file(path);
    const bool gzipped = looks_gzipped(bytes);
    if (gzipped) {
        LoadProgressShare inflating(0.0, kInflateShare);
        std::optional<size_t> limit;  // known once the header has inflated
        bytes = read_gzip_file(path, bytes, [&](std::string_view inflated) {
            if (limit) return *limit;
            const size_t keyword = inflated.find("end_header");
            if (keyword != std::string_view::npos && inflated.find('\n', keyword) != std::string_view::npos) {
                try {
                    limit = saturating_add(largest_body(parse_header(file, inflated)), kInflationMargin);
                    return *limit;
                } catch (const Error&) {
                    // "end_header" in a comment, or a bad header: judged once the whole header has inflated.
                    if (inflated.size() > kMaxHeaderBytes) throw;
                }
            }
            if (inflated.size() > kMaxHeaderBytes) parse_header(file, inflated);  // throws: says what is wrong
            return std::numeric_limits<size_t>::max();
        });
    }
    LoadProgressShare parsing(gzipped ? kInflateShare : 0.0, 1.0);
    const std::string_view view(bytes);
    const Header header = parse_header(file, view);
    const char* body = bytes.data() + header.body_offset;
    const char* end = bytes.data() + bytes.size();
    PlyDetails ignored;
    PlyDetails& out = details ? *details : ignored;
    out.texture_files = header.texture_files;
    std::vector<glm::vec2> corner_uvs;
    Mesh mesh;
    switch (header.format) {
        case Format::Ascii:
            mesh = read_body(file, view, header, AsciiSource(body, end), out.warnings, corner_uvs);
            break;
        case Format::BinaryLittleEndian:
            mesh = read_body(file, view, header, BinarySource<std::endian::native == std::endian::big>(body, end),
                             out.warnings, corner_uvs);
            break;
        case Format::BinaryBigEndian:
            mesh = read_body(file, view, header, BinarySource<std::endian::native == std::endian::little>(body, end),
                             out.warnings, corner_uvs);
            break;
    }
    std::string name = path.filename().string();
    if (name.size() > 3 && name.ends_with(".gz")) name.resize(name.size() - 3);
    mesh.name = std::filesystem::path(name).stem().string();
    // Normals before the seams are split, so a vertex split by its texture coordinates stays smooth.
    if (mesh.normals.empty()) compute_smooth_normals(mesh);
    if (!corner_uvs.empty()) apply_corner_uvs(mesh, corner_uvs);
    return mesh;
}

}  // namespace prism
