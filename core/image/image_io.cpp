// Texture loading and render output through stb_image / stb_image_write (implementations live in Debian's libstb);
// WebP textures through libwebp (image_webp.h).
#include "core/image/image_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <system_error>
#include <vector>

#include <unistd.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include "core/util/error.h"
#include "core/image/image_guard.h"
#include "core/image/image_webp.h"
#include "core/util/input_file.h"
#include "core/util/scene_read_rules.h"
#include "core/image/rgbe.h"

namespace prism {
namespace {

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
}

std::string stb_reason() {
    const char* reason = stbi_failure_reason();
    // Some failures come with an empty reason (stb names an unknown critical PNG chunk by its type, and a type
    // starting with a NUL byte reads as ""); the report must still say something.
    return reason && *reason ? reason : "unreadable image";
}

struct StbFree {
    void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// Writes through `write` into a temporary sibling, then renames it into place: a reader never sees half a file
// and a failed write leaves nothing behind.
template <typename WriteFunction>
void write_atomically(const std::filesystem::path& path, WriteFunction write) {
    std::filesystem::path temporary = path;
    temporary += ".tmp-" + std::to_string(::getpid());
    errno = 0;
    if (!write(temporary.string().c_str())) {
        int saved = errno;
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw file_error(path.string(),
                         std::string("cannot write (") + (saved ? std::strerror(saved) : "image encoder failed") + ")");
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw file_error(path.string(), "cannot write (" + error.message() + ")");
    }
}

void check_image_size(const std::filesystem::path& path, int width, int height, size_t values, size_t per_pixel) {
    if (width <= 0 || height <= 0)
        throw file_error(path.string(), "cannot write an image of " + std::to_string(width) + "x" +
                                            std::to_string(height) + " pixels");
    if (values < static_cast<size_t>(width) * static_cast<size_t>(height) * per_pixel)
        throw file_error(path.string(), "cannot write (pixel buffer smaller than the image)");
}

// An 8-bit RGBA image as texels: sRGB for colour data (base colour, emissive), linear for the rest.
Texture texture_of_rgba8(const uint8_t* rgba, int width, int height, const std::string& name, bool color_data) {
    Texture texture;
    texture.name = name;
    texture.width = width;
    texture.height = height;
    texture.encoding = color_data ? TextureEncoding::Srgb8 : TextureEncoding::Linear8;
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height);
    texture.texels.resize(count);
    for (size_t i = 0; i < count; ++i) {
        const uint8_t* p = rgba + 4 * i;
        texture.texels[i] = uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
    }
    return texture;
}

}  // namespace

Texture load_texture_from_memory(std::span<const uint8_t> bytes, const std::string& name, bool color_data) {
    if (bytes.empty()) throw file_error(name, "empty image file");
    if (bytes.size() > static_cast<size_t>(INT32_MAX)) throw file_error(name, "image file too large");
    if (is_webp(bytes)) {
        Rgba8Pixels pixels = decode_webp(bytes, name);
        return texture_of_rgba8(pixels.rgba.data(), pixels.width, pixels.height, name, color_data);
    }
    check_encoded_image(bytes, name);
    const int length = static_cast<int>(bytes.size());
    int declared_width = 0, declared_height = 0, declared_channels = 0;
    if (stbi_info_from_memory(bytes.data(), length, &declared_width, &declared_height, &declared_channels))
        charge_texture_bytes(
            name, uint64_t(std::max(declared_width, 0)) * uint64_t(std::max(declared_height, 0)) * sizeof(uint32_t));
    Texture texture;
    texture.name = name;
    int channels = 0;
    if (stbi_is_hdr_from_memory(bytes.data(), length)) {
        std::unique_ptr<float, StbFree> pixels(
            stbi_loadf_from_memory(bytes.data(), length, &texture.width, &texture.height, &channels, 3));
        if (!pixels) throw file_error(name, stb_reason());
        texture.encoding = TextureEncoding::Rgbe;
        const size_t count = static_cast<size_t>(texture.width) * static_cast<size_t>(texture.height);
        texture.texels.resize(count);
        const float* rgb = pixels.get();
        for (size_t i = 0; i < count; ++i)
            texture.texels[i] = pack_rgbe(glm::vec3(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
        return texture;
    }
    std::unique_ptr<uint8_t, StbFree> pixels(
        stbi_load_from_memory(bytes.data(), length, &texture.width, &texture.height, &channels, 4));
    if (!pixels) throw file_error(name, stb_reason());
    return texture_of_rgba8(pixels.get(), texture.width, texture.height, name, color_data);
}

Texture load_texture(const std::filesystem::path& path, bool color_data) {
    const std::string bytes = read_input_file(path);
    return load_texture_from_memory(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()),
                                    path.string(), color_data);
}

std::filesystem::path find_file_case_insensitive(const std::filesystem::path& directory, const std::string& relative) {
    std::string normalised = relative;
    std::replace(normalised.begin(), normalised.end(), '\\', '/');
    if (normalised.empty()) return {};
    std::error_code error;
    std::filesystem::path current = normalised.front() == '/' ? std::filesystem::path("/") : directory;
    size_t start = 0;
    while (start <= normalised.size()) {
        size_t end = normalised.find('/', start);
        if (end == std::string::npos) end = normalised.size();
        std::string component = normalised.substr(start, end - start);
        start = end + 1;
        if (component.empty() || component == ".") continue;
        if (component == "..") {
            current /= "..";
            continue;
        }
        if (std::filesystem::exists(current / component, error)) {
            current /= component;
            continue;
        }
        // The exact name is missing: take the first directory entry equal to it ignoring case.
        const std::string wanted = lowercase(component);
        std::filesystem::path match;
        for (std::filesystem::directory_iterator it(current, error), end_it; !error && it != end_it;
             it.increment(error)) {
            if (lowercase(it->path().filename().string()) == wanted) {
                match = it->path();
                break;
            }
        }
        if (match.empty()) return {};
        current = match;
    }
    if (!std::filesystem::is_regular_file(current, error)) return {};
    return current;
}

void write_png(const std::filesystem::path& path, int width, int height, std::span<const uint32_t> rgba8) {
    check_image_size(path, width, height, rgba8.size(), 1);
    // Unpack explicitly rather than reinterpret the words, so the byte order does not depend on the host.
    std::vector<uint8_t> bytes(static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
    for (size_t i = 0; i < bytes.size() / 4; ++i) {
        const uint32_t texel = rgba8[i];
        bytes[4 * i + 0] = static_cast<uint8_t>(texel);
        bytes[4 * i + 1] = static_cast<uint8_t>(texel >> 8);
        bytes[4 * i + 2] = static_cast<uint8_t>(texel >> 16);
        bytes[4 * i + 3] = static_cast<uint8_t>(texel >> 24);
    }
    write_atomically(
        path, [&](const char* file) { return stbi_write_png(file, width, height, 4, bytes.data(), width * 4) != 0; });
}

void write_hdr(const std::filesystem::path& path, int width, int height, std::span<const float> rgba) {
    check_image_size(path, width, height, rgba.size(), 4);
    write_atomically(path, [&](const char* file) { return stbi_write_hdr(file, width, height, 4, rgba.data()) != 0; });
}

void check_output_extension(const std::filesystem::path& path) {
    const std::string extension = lowercase(path.extension().string());
    if (extension != ".png" && extension != ".hdr")
        throw file_error(path.string(),
                         "unsupported output format '" + path.extension().string() + "' (use .png or .hdr)");
}

}  // namespace prism
