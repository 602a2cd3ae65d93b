// OpenEXR output through tinyexr (Debian's libtinyexr-dev): the linear radiance as half floats, unclamped.
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <tinyexr.h>

#include "core/util/error.h"
#include "core/image/image_output.h"
#include "core/util/output_file.h"

namespace prism {

void write_exr(const std::filesystem::path& path, int width, int height, std::span<const float> rgba) {
    if (width <= 0 || height <= 0 || rgba.size() < size_t(width) * size_t(height) * 4)
        throw file_error(path.string(), "cannot write (pixel buffer smaller than the image)");
    const size_t pixels = size_t(width) * size_t(height);
    // EXR readers expect the channels sorted by name: B, G, R.
    const char* names[3] = {"B", "G", "R"};
    const int source_channel[3] = {2, 1, 0};
    std::vector<std::vector<float>> planes(3, std::vector<float>(pixels));
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < pixels; ++i) planes[size_t(c)][i] = rgba[4 * i + size_t(source_channel[c])];
    float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};

    std::vector<EXRChannelInfo> channels(3);
    std::vector<int> given_types(3, TINYEXR_PIXELTYPE_FLOAT), stored_types(3, TINYEXR_PIXELTYPE_HALF);
    for (int c = 0; c < 3; ++c) {
        std::memset(&channels[size_t(c)], 0, sizeof(EXRChannelInfo));
        std::strncpy(channels[size_t(c)].name, names[c], sizeof channels[size_t(c)].name - 1);
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 3;
    header.channels = channels.data();
    header.pixel_types = given_types.data();
    header.requested_pixel_types = stored_types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = 3;
    image.width = width;
    image.height = height;
    image.images = reinterpret_cast<unsigned char**>(plane_pointers);

    unsigned char* memory = nullptr;
    const char* error = nullptr;
    size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error);
    std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    if (size == 0 || !memory) {
        std::string cause = error ? error : "encoder failed";
        if (error) FreeEXRErrorMessage(error);
        throw file_error(path.string(), "cannot write EXR (" + cause + ")");
    }
    write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(memory), size));
}

}  // namespace prism
