// The resolve stage's display transform: the frame's linear light scaled by the exposure, then, when asked for,
// compressed by a tone map before sRGB encoding. The seed has neither: its images clip at 1, which Prism keeps by
// default (exposure 0, no tone map).
#ifndef RT_DISPLAY_H
#define RT_DISPLAY_H

#include "math.h"

// Khronos PBR Neutral (Khronos 3D Commerce, 2024): colours below 0.76 pass unchanged but for a small offset that
// lifts the darkest channel's toe, brighter ones are compressed towards 1 and desaturated as they approach it, so a
// glTF material's base colour keeps its hue under light where a plain clip turns it white.
RT_FUNC float3 rt_tone_map_neutral(float3 color) {
    const float start_compression = 0.8f - 0.04f;
    const float desaturation = 0.15f;
    float x = rt_min(color.x, rt_min(color.y, color.z));
    float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    color = color - make_float3(offset, offset, offset);
    float peak = rt_max(color.x, rt_max(color.y, color.z));
    if (peak < start_compression) return color;
    const float d = 1.0f - start_compression;
    float new_peak = 1.0f - d * d / (peak + d - start_compression);
    color = color * (new_peak / peak);
    float g = 1.0f - 1.0f / (desaturation * (peak - new_peak) + 1.0f);
    return color * (1.0f - g) + make_float3(new_peak, new_peak, new_peak) * g;
}

// What a pixel of `radiance` (the frame's light, already times the exposure) shows before sRGB encoding.
RT_FUNC float3 rt_display_color(float3 radiance, bool tone_map_neutral) {
    return tone_map_neutral ? rt_tone_map_neutral(radiance) : radiance;
}

#endif
