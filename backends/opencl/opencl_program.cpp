#include "backends/opencl/opencl_program.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism::opencl {
namespace {

// The fixed build options (docs/fairness.md). No fast-math flags; FP_CONTRACT stays at the OpenCL C default (on),
// as nvcc's default --fmad=true; divide and sqrt correctly rounded where the device supports it, as CUDA's
// default -prec-div=true -prec-sqrt=true.
// NVIDIA's compiler takes inline PTX: there the queue slots are taken a warp at a time with PTX warp votes and
// shuffles (kernels/compat/opencl.h, RT_QUEUE_RESERVE).
std::string build_options(const DeviceEntry& device, const std::string& extra_options) {
    std::string options = "-cl-std=CL1.2";
    if (device.fp_config & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) options += " -cl-fp32-correctly-rounded-divide-sqrt";
    if (device.platform_vendor.find("NVIDIA") != std::string::npos && (device.type & CL_DEVICE_TYPE_GPU))
        options += " -D RT_OPENCL_NVIDIA_PTX";
    if (!extra_options.empty()) options += " " + extra_options;
    // Experiments only (docs/environment.md): the options are part of the cache key, so a binary built with them
    // is never taken for one built without.
    if (std::optional<std::string> extra = setting(Setting::OpenclOptions); extra && !extra->empty())
        options += " " + *extra;
    return options;
}

uint64_t fnv1a(const std::string& text, uint64_t hash) {
    for (unsigned char c : text) {
        hash ^= c;
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::string hex64(uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

std::string read_file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The first meaningful lines of a build log, on one line.
std::string log_excerpt(const std::string& log) {
    std::istringstream in(log);
    std::string line, out;
    int lines = 0;
    while (std::getline(in, line) && lines < 8) {
        line = trim(line);
        if (line.empty()) continue;
        out += (out.empty() ? "" : " | ") + line;
        ++lines;
    }
    if (out.size() > 1500) out = out.substr(0, 1500) + " ...";
    return out.empty() ? "(empty build log)" : out;
}

std::string build_log(cl_program program, const DeviceEntry& device) {
    size_t size = 0;
    clGetProgramBuildInfo(program, device.device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
    std::string log(size, '\0');
    if (size) clGetProgramBuildInfo(program, device.device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    return log;
}

}  // namespace

std::string cache_dir() {
    if (std::optional<std::string> dir = setting(Setting::CacheDir)) return *dir;  // "": no cache
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/prism";
    if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/prism";
    return "";
}

cl_program build_program(const ClDevice& dev, const std::string& source, const std::string& extra_options,
                         opencl_internal::BuildReport* report) {
    const DeviceEntry& device = dev.entry();
    const std::string options = build_options(device, extra_options);
    const std::string key = "prism-opencl-v1\n" + options + "\n" + device.platform_name + "\n" +
                            device.platform_version + "\n" + device.device_name + "\n" + device.device_version + "\n" +
                            device.driver_version + "\n" + source;
    const std::string hash = hex64(fnv1a(key, 0xcbf29ce484222325ull)) + hex64(fnv1a(key, 0x84222325cbf29ce4ull));
    const std::string header = "PRISMCL " + hash + " " + std::to_string(key.size()) + "\n";
    std::string dir = cache_dir();
    std::string file = dir.empty() ? "" : dir + "/opencl-" + hash + ".bin";
    if (report) {
        report->device = device.device_name;
        report->options = options;
        report->from_cache = false;
        report->cache_file = file;
    }
    cl_int err = CL_SUCCESS;

    if (!file.empty()) {
        std::string bytes = read_file_bytes(file);
        if (bytes.size() > header.size() && bytes.compare(0, header.size(), header) == 0) {
            const unsigned char* binary = reinterpret_cast<const unsigned char*>(bytes.data() + header.size());
            size_t binary_size = bytes.size() - header.size();
            cl_int status = CL_SUCCESS;
            cl_program program =
                clCreateProgramWithBinary(dev.context(), 1, &device.device, &binary_size, &binary, &status, &err);
            if (err == CL_SUCCESS && status == CL_SUCCESS &&
                clBuildProgram(program, 1, &device.device, options.c_str(), nullptr, nullptr) == CL_SUCCESS) {
                if (report) report->from_cache = true;
                return program;
            }
            if (program) clReleaseProgram(program);
        }
    }

    const char* text = source.c_str();
    size_t length = source.size();
    cl_program program = clCreateProgramWithSource(dev.context(), 1, &text, &length, &err);
    check(err, "clCreateProgramWithSource", device);
    err = clBuildProgram(program, 1, &device.device, options.c_str(), nullptr, nullptr);
    if (err != CL_SUCCESS) {
        std::string log = build_log(program, device);
        clReleaseProgram(program);
        throw Error("opencl: kernel build failed on " + device.device_name + ": " + log_excerpt(log));
    }

    // Store the binary; any failure only means no caching (read-only home, full disk, ...).
    if (!file.empty()) {
        size_t binary_size = 0;
        if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof binary_size, &binary_size, nullptr) ==
                CL_SUCCESS &&
            binary_size > 0) {
            std::string binary(binary_size, '\0');
            unsigned char* pointer = reinterpret_cast<unsigned char*>(binary.data());
            if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof pointer, &pointer, nullptr) == CL_SUCCESS) {
                std::error_code ec;
                std::filesystem::create_directories(dir, ec);
                std::string temp = file + ".tmp" + std::to_string(::getpid());
                {
                    std::ofstream out(temp, std::ios::binary);
                    out << header << binary;
                    out.close();
                    if (!out) std::filesystem::remove(temp, ec);
                }
                if (std::filesystem::exists(temp, ec)) {
                    std::filesystem::rename(temp, file, ec);
                    if (ec) std::filesystem::remove(temp, ec);
                }
            }
        }
    }
    return program;
}

}  // namespace prism::opencl
