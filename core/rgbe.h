// Radiance RGBE texels: three 8-bit mantissas sharing one exponent byte, packed like RGBA8 (r in the low byte,
// the exponent in the high byte). value = mantissa * 2^(exponent - 136); exponent 0 means black. This is the
// decoding stb_image and the kernels use (no half-step bias), so encoding rounds to nearest to halve the error.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace prism {

inline uint32_t pack_rgbe(glm::vec3 color) {
    // Negative and NaN channels carry no light; clamp them rather than let them poison the shared exponent.
    float r = color.x > 0.0f ? color.x : 0.0f;
    float g = color.y > 0.0f ? color.y : 0.0f;
    float b = color.z > 0.0f ? color.z : 0.0f;
    float largest = std::max(r, std::max(g, b));
    if (!(largest >= 0x1p-128f)) return 0u;   // below the smallest representable step (also catches NaN)
    if (std::isinf(largest)) largest = r = g = b = 0x1p127f;
    int exponent = 0;
    std::frexp(largest, &exponent);           // largest = f * 2^exponent, f in [0.5, 1)
    // Rounding the largest channel can carry to 256: then the shared exponent must grow by one.
    if (std::lround(std::ldexp(largest, 8 - exponent)) > 255) exponent += 1;
    int biased = exponent + 128;
    if (biased > 255) {   // beyond the format's range: saturate
        biased = 255;
        exponent = 127;
        r = std::min(r, 0x1p127f), g = std::min(g, 0x1p127f), b = std::min(b, 0x1p127f);
    }
    auto mantissa = [exponent](float channel) {
        long m = std::lround(std::ldexp(channel, 8 - exponent));
        return static_cast<uint32_t>(std::clamp(m, 0L, 255L));
    };
    return mantissa(r) | (mantissa(g) << 8) | (mantissa(b) << 16) | (static_cast<uint32_t>(biased) << 24);
}

inline glm::vec3 unpack_rgbe(uint32_t texel) {
    uint32_t biased = texel >> 24;
    if (biased == 0u) return glm::vec3(0.0f);
    float scale = std::ldexp(1.0f, static_cast<int>(biased) - 136);
    return glm::vec3(static_cast<float>(texel & 0xffu), static_cast<float>((texel >> 8) & 0xffu),
                     static_cast<float>((texel >> 16) & 0xffu)) * scale;
}

}  // namespace prism
