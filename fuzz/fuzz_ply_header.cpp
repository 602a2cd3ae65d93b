// PLY headers with the body held fixed: the input is a header (up to and with "end_header"; added when missing),
// followed by a 3-vertex triangle body and, in the .ply.gz copy, a second gzip member of 2 MiB of blanks (more
// than the reader's margin, so the inflation cap is reached; compressed once, so each run stays fast). Element counts,
// property lists and types are what the fuzzer varies; the reader must size nothing from a count the bytes do not back,
// and the gzip reader must stop inflating where the header's counts end. Dictionary: fuzz/dict/ply.dict.
#include <string>

#include <zlib.h>

#include "fuzz/fuzz_support.h"

namespace {

std::string gzip(const std::string& bytes) {
    z_stream stream{};
    deflateInit2(&stream, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    std::string out(deflateBound(&stream, bytes.size()), '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    stream.avail_in = static_cast<uInt>(bytes.size());
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    deflate(&stream, Z_FINISH);
    out.resize(out.size() - stream.avail_out);
    deflateEnd(&stream);
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string header(prism::fuzz::as_text(data, size));
    const size_t end = header.find("end_header\n");
    if (end == std::string::npos)
        header += "\nend_header\n";
    else
        header.resize(end + 11);
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const auto plain = prism::fuzz::scratch_dir() / "header.ply";
    prism::fuzz::write_file(plain, header + body);
    prism::fuzz::load_and_build(plain);
    const auto compressed = prism::fuzz::scratch_dir() / "header.ply.gz";
    static const std::string blanks = gzip(std::string(size_t(2) << 20, ' '));
    prism::fuzz::write_file(compressed, gzip(header + body) + blanks);
    prism::fuzz::load_and_build(compressed);
    return 0;
}
