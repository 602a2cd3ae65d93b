#include "core/image/image_guard_formats.h"

#include "core/util/error.h"

namespace prism::image_guard {

// PNG: each chunk's declared length must fit in what is left of the file. stb_image 2.27 grows its IDAT buffer to
// the declared length before reading it (fuzz_image: a 2 KB file made it allocate 1.5 GB); with this check it
// never holds more than the file's size. A missing CRC after the last chunk is tolerated, as stb tolerates it.
void check_png(std::span<const uint8_t> bytes, const std::string& name) {
    size_t at = 8;  // after the signature
    while (at + 8 <= bytes.size()) {
        const uint64_t length =
            uint64_t(bytes[at]) << 24 | uint64_t(bytes[at + 1]) << 16 | uint64_t(bytes[at + 2]) << 8 | bytes[at + 3];
        const std::string type(reinterpret_cast<const char*>(bytes.data() + at + 4), 4);
        const uint64_t left = bytes.size() - (at + 8);
        if (length > left)
            throw file_error(name, "corrupt PNG (a chunk declares " + std::to_string(length) + " bytes; " +
                                       std::to_string(left) + " are left in the file)");
        if (type == "IEND") return;
        at += 12 + length;
    }
}

}  // namespace prism::image_guard
