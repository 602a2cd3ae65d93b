#include "apps/option_checks.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "core/util/error.h"
#include "core/render/host_memory.h"
#include "core/image/image_io.h"

namespace prism::app {

void check_backend_option(const std::string& backend) {
    // A comma list splits a render over several backends (apps/render_distributed.h): each entry is checked.
    for (size_t start = 0; start <= backend.size();) {
        size_t end = backend.find(',', start);
        if (end == std::string::npos) end = backend.size();
        const std::string entry = backend.substr(start, end - start);
        start = end + 1;
        const size_t colon = entry.find(':');
        if (colon == std::string::npos) continue;
        const std::string api = entry.substr(0, colon), device = entry.substr(colon + 1);
        if ((api == "cpu" || api == "cpu-ref") && device != "0" && device != "all")
            throw Error("--backend " + shorten(backend) + ": " + api + " has one device, " + api + ":0");
    }
}

void check_min_weight_option(float min_weight) {
    if (!(min_weight >= 0.0f && min_weight <= 1.0f))  // NaN fails both comparisons
        throw Error("--min-weight " + std::to_string(min_weight) + ": expected a number from 0 to 1");
}

void check_writable_option(const std::string& option, const std::string& path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) throw Error(option + " " + shorten_path(path) + ": is a directory");
    std::filesystem::path probe = path;
    probe += ".probe-" + std::to_string(::getpid());
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NONBLOCK, 0600);
    if (fd < 0) throw Error(option + " " + shorten_path(path) + ": cannot write there (" + std::strerror(errno) + ")");
    ::close(fd);
    ::unlink(probe.c_str());
}

void check_frame_options(const std::string& backend, const RenderSettings& settings) {
    check_backend_option(backend);
    check_render_settings(settings);
    check_min_weight_option(settings.min_weight);
    check_host_memory(frame_host_bytes(settings, frame_arrays_of(backend)),
                      "--width " + std::to_string(settings.width) + " --height " + std::to_string(settings.height) +
                          " on " + shorten(backend));
}

void check_render_options(const std::string& backend, const RenderSettings& settings, const std::string& out,
                          const std::string& stats) {
    check_backend_option(backend);
    check_render_settings(settings);
    check_min_weight_option(settings.min_weight);
    check_writable_option("--out", out);
    if (!stats.empty()) {
        std::error_code error;
        if (stats == out || std::filesystem::equivalent(stats, out, error))
            throw Error("--stats " + shorten_path(stats) + ": the same file as --out");
        check_writable_option("--stats", stats);
    }
    check_host_memory(frame_host_bytes(settings, frame_arrays_of(backend)),
                      "--width " + std::to_string(settings.width) + " --height " + std::to_string(settings.height) +
                          " on " + shorten(backend));
}

}  // namespace prism::app
