#include "core/render/host_memory.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <optional>

#include <sys/resource.h>
#include <unistd.h>

#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism {
namespace {

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

std::optional<uint64_t> limit_from_environment() {
    std::optional<std::string> text = setting(Setting::HostMemoryLimit);
    if (!text || text->empty()) return std::nullopt;
    const std::string& value = *text;
    if (!std::all_of(value.begin(), value.end(), [](unsigned char c) { return std::isdigit(c); }))
        throw Error("PRISM_HOST_MEMORY_LIMIT='" + shorten(value) + "' is not a byte count");
    try {
        return std::stoull(value);
    } catch (const std::exception&) {
        throw Error("PRISM_HOST_MEMORY_LIMIT='" + shorten(value) + "' is out of range");
    }
}

}  // namespace

namespace {

struct Limit {
    uint64_t bytes;
    const char* source;
};

Limit find_limit() {
    if (std::optional<uint64_t> limit = limit_from_environment()) return {*limit, "PRISM_HOST_MEMORY_LIMIT"};
    const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGE_SIZE);
    Limit limit{pages > 0 && page_size > 0 ? uint64_t(pages) * uint64_t(page_size) : UINT64_MAX,
                "this machine's memory"};
    struct rlimit address_space {};
    if (::getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY &&
        address_space.rlim_cur < limit.bytes)
        limit = {uint64_t(address_space.rlim_cur), "the address-space limit"};
    return limit;
}

}  // namespace

uint64_t host_memory_limit() { return find_limit().bytes; }

uint64_t frame_host_bytes(const RenderSettings& settings, FrameArrays arrays) {
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    // The frame Prism keeps (packed RGBA8, and float RGBA for .hdr) and about as much again while encoding it.
    uint64_t bytes = pixels * (2 * sizeof(uint32_t) + (settings.read_radiance ? 2 * sizeof(float4) : 0));
    if (arrays != FrameArrays::Device)
        bytes += pixels * (RT_ACCUM_WORDS_PER_PIXEL * sizeof(uint32_t) + sizeof(uint32_t) + sizeof(float4));
    if (arrays == FrameArrays::HostWavefront) {
        const double factor = std::max(settings.queue_factor, 1.0f);
        const uint64_t rays = uint64_t(double(pixels) * factor);
        bytes += rays * (2 * sizeof(Ray) + sizeof(Hit) + sizeof(ShadowRay));
    }
    return bytes;
}

FrameArrays frame_arrays_of(const std::string& backend) {
    const std::string api = backend.substr(0, backend.find(':'));
    if (api == "cpu-ref") return FrameArrays::HostReference;
    if (api == "cpu" || api == "auto") return FrameArrays::HostWavefront;
    return FrameArrays::Device;
}

void check_host_memory(uint64_t bytes, const std::string& what) {
    const Limit limit = find_limit();
    if (bytes <= limit.bytes) return;
    throw Error(what + ": needs about " + mib(bytes) + " of host memory, over the limit of " + mib(limit.bytes) + " (" +
                limit.source + ")");
}

}  // namespace prism
