#include "core/util/input_file.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/util/error.h"
#include "core/util/non_copyable.h"

namespace prism {
namespace {

// Why a file of this type is not read, or nullptr for a regular file.
const char* refusal(mode_t mode) {
    if (S_ISREG(mode)) return nullptr;
    if (S_ISDIR(mode)) return "is a directory, not a file";
    if (S_ISFIFO(mode)) return "is a FIFO (named pipe), not a regular file";
    if (S_ISCHR(mode) || S_ISBLK(mode)) return "is a device, not a regular file";
    if (S_ISSOCK(mode)) return "is a socket, not a regular file";
    return "is not a regular file";
}

class Descriptor : private NonCopyable {
public:
    explicit Descriptor(int fd) : fd_(fd) {}
    ~Descriptor() {
        if (fd_ >= 0) ::close(fd_);
    }
    int get() const { return fd_; }

private:
    int fd_;
};

}  // namespace

void require_regular_file(const std::filesystem::path& path) {
    struct stat status {};
    if (::stat(path.c_str(), &status) != 0) {
        if (errno == ENOENT) throw file_error(path.string(), "no such file");
        throw file_error(path.string(), std::string("cannot open (") + std::strerror(errno) + ")");
    }
    if (const char* cause = refusal(status.st_mode)) throw file_error(path.string(), cause);
}

std::string read_input_file(const std::filesystem::path& path) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
    Descriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
    if (fd.get() < 0) throw file_error(path.string(), std::string("cannot open (") + std::strerror(errno) + ")");
    struct stat status {};
    if (::fstat(fd.get(), &status) != 0)
        throw file_error(path.string(), std::string("cannot read (") + std::strerror(errno) + ")");
    if (const char* cause = refusal(status.st_mode)) throw file_error(path.string(), cause);
    std::string bytes;
    bytes.reserve(static_cast<size_t>(status.st_size));
    char chunk[1 << 16];
    for (;;) {
        const ssize_t got = ::read(fd.get(), chunk, sizeof chunk);
        if (got == 0) break;
        if (got < 0) {
            if (errno == EINTR) continue;
            throw file_error(path.string(), std::string("read error (") + std::strerror(errno) + ")");
        }
        bytes.append(chunk, static_cast<size_t>(got));
    }
    return bytes;
}

}  // namespace prism
