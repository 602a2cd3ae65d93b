#include "core/util/standard_output.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "core/util/error.h"

namespace prism {
namespace {

int data_descriptor = STDOUT_FILENO;

void point_stdout_at(int descriptor) {
    std::fflush(stdout);
    if (::dup2(descriptor, STDOUT_FILENO) < 0)
        throw Error(std::string("standard output: cannot redirect (") + std::strerror(errno) + ")");
}

}  // namespace

void reserve_standard_output_for_data() {
    if (data_descriptor != STDOUT_FILENO) return;
    std::fflush(stdout);
    int saved = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    if (saved < 0) throw Error(std::string("standard output: cannot reserve (") + std::strerror(errno) + ")");
    data_descriptor = saved;
    point_stdout_at(STDERR_FILENO);
}

void silence_standard_output() {
    int null_device = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null_device < 0) throw Error(std::string("/dev/null: cannot open (") + std::strerror(errno) + ")");
    point_stdout_at(null_device);
    ::close(null_device);
}

void write_standard_output(std::string_view bytes) {
    std::fflush(stdout);
    while (!bytes.empty()) {
        ssize_t written = ::write(data_descriptor, bytes.data(), bytes.size());
        if (written < 0 && errno == EINTR) continue;
        if (written <= 0) throw Error(std::string("standard output: write failed (") + std::strerror(errno) + ")");
        bytes.remove_prefix(size_t(written));
    }
}

}  // namespace prism
