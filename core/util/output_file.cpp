#include "core/util/output_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "core/util/error.h"

namespace prism {

namespace {

void write_temporary(const std::filesystem::path& path, const std::filesystem::path& temporary,
                     std::string_view bytes) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path.string() + ": cannot write (" + std::strerror(errno) + ")");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw Error(path.string() + ": write failed (" + std::strerror(errno) + ")");
    }
}

std::filesystem::path temporary_name(const std::filesystem::path& path) {
    std::filesystem::path temporary = path;
    temporary += ".tmp-" + std::to_string(getpid());
    return temporary;
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
    const std::filesystem::path temporary = temporary_name(path);
    write_temporary(path, temporary, bytes);
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw Error(path.string() + ": cannot write (" + ec.message() + ")");
    }
}

StagedOutput::StagedOutput(std::filesystem::path path, std::string_view bytes)
    : path_(std::move(path)), temporary_(temporary_name(path_)) {
    write_temporary(path_, temporary_, bytes);
}

StagedOutput::~StagedOutput() {
    std::error_code ignored;
    if (!committed_) std::filesystem::remove(temporary_, ignored);
}

void StagedOutput::commit() {
    std::error_code error;
    std::filesystem::rename(temporary_, path_, error);
    if (error) throw Error(path_.string() + ": cannot write (" + error.message() + ")");
    committed_ = true;
}

}  // namespace prism
