// Radiance RGBE texels: three 8-bit mantissas sharing one exponent byte, packed like RGBA8 (r in the low byte,
// the exponent in the high byte). Encoding truncates (Ward's float2rgbe) and decoding takes the middle of the
// step, (m + 0.5) * 2^(e - 136), as Ward's reference reader and kernels/texture.h do: together they round to
// nearest, so the error is at most half a step (0.4% of the brightest channel). Exponent byte 0 means black.
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
    const float limit = 0x1.fep126f;  // 255 * 2^(255 - 136): the largest mantissa at the largest exponent
    r = std::min(r, limit), g = std::min(g, limit), b = std::min(b, limit);
    const float largest = std::max(r, std::max(g, b));
    if (!(largest >= 0x1p-128f)) return 0u;  // below the smallest representable step
    int exponent = 0;
    std::frexp(largest, &exponent);  // largest = f * 2^exponent, f in [0.5, 1): mantissa in [128, 255]
    auto mantissa = [exponent](float channel) {
        const float scaled = std::ldexp(channel, 8 - exponent);
        return static_cast<uint32_t>(std::min(scaled, 255.0f));  // truncation; decoding adds the half step
    };
    return mantissa(r) | (mantissa(g) << 8) | (mantissa(b) << 16) | (static_cast<uint32_t>(exponent + 128) << 24);
}

inline glm::vec3 unpack_rgbe(uint32_t texel) {
    const uint32_t biased = texel >> 24;
    if (biased == 0u) return glm::vec3(0.0f);
    const float scale = std::ldexp(1.0f, static_cast<int>(biased) - 136);
    return (glm::vec3(static_cast<float>(texel & 0xffu), static_cast<float>((texel >> 8) & 0xffu),
                      static_cast<float>((texel >> 16) & 0xffu)) +
            0.5f) *
           scale;
}

}  // namespace prism
