// Texture reads from the shared texel array: the same filters, wrap modes and decoding on every API (no hardware
// samplers, whose filtering precision differs between vendors and would break cross-API agreement).
#ifndef RT_TEXTURE_H
#define RT_TEXTURE_H

#include "globals.h"
#include "math.h"

RT_FUNC float rt_srgb_to_linear(float c) {
    return c <= 0.04045f ? c * (1.0f / 12.92f) : rt_pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

// An 8-bit sRGB value (0-255) in linear terms: rt_srgb_to_linear of value / 255. The cpu backends read the same
// values from a table built once per stage build: a pow per channel per texel took about half of their miss and
// shade stages' time on a textured glTF under a cube map (docs/kernels.md). The GPUs keep the pow.
#if defined(RT_CPU)
struct RtSrgb8Table {
    float linear[256];
};
RT_FUNC RtSrgb8Table rt_make_srgb8_table() {
    RtSrgb8Table table{};
    for (uint v = 0u; v < 256u; ++v) table.linear[v] = rt_srgb_to_linear(rt_float(v) * (1.0f / 255.0f));
    return table;
}
// Built when the program starts (one per stage build), so a read pays no initialization check.
static const RtSrgb8Table rt_srgb8_table = rt_make_srgb8_table();
RT_FUNC float rt_srgb8_to_linear(uint value) { return rt_srgb8_table.linear[value & 255u]; }
#else
RT_FUNC float rt_srgb8_to_linear(uint value) { return rt_srgb_to_linear(rt_float(value) * (1.0f / 255.0f)); }
#endif

RT_FUNC float rt_linear_to_srgb(float c) {
    c = rt_clamp01(c);
    return c <= 0.0031308f ? c * 12.92f : 1.055f * rt_pow(c, 1.0f / 2.4f) - 0.055f;
}

RT_FUNC float4 rt_decode_texel(uint texel, uint encoding) {
    float r = rt_float(texel & 255u);
    float g = rt_float((texel >> 8u) & 255u);
    float b = rt_float((texel >> 16u) & 255u);
    uint e = texel >> 24u;
    if (encoding == RT_TEXENC_RGBE) {
        // Radiance RGBE: mantissas share the exponent; (m + 0.5) * 2^(e - 136) as in Ward's reference reader.
        if (e == 0u) return make_float4(0.0f, 0.0f, 0.0f, 1.0f);
        float scale = rt_ldexp(1.0f, rt_int(e) - 136);
        return make_float4((r + 0.5f) * scale, (g + 0.5f) * scale, (b + 0.5f) * scale, 1.0f);
    }
    float inv = 1.0f / 255.0f;
    if (encoding == RT_TEXENC_SRGB8)
        return make_float4(rt_srgb8_to_linear(texel & 255u), rt_srgb8_to_linear((texel >> 8u) & 255u),
                           rt_srgb8_to_linear((texel >> 16u) & 255u), rt_float(e) * inv);
    return make_float4(r * inv, g * inv, b * inv, rt_float(e) * inv);
}

// i modulo size in [0, size). GLSL leaves % undefined when an operand is negative (drivers may answer as C does,
// or not), so % only ever sees non-negative values here.
RT_FUNC int rt_wrap_repeat(int i, int size) {
    if (i >= 0) return i % size;
    return size - 1 - (-1 - i) % size;
}

// glTF sampler wrap modes (RT_WRAP_*) on an integer texel coordinate.
RT_FUNC int rt_wrap(int i, int size, uint mode) {
    if (mode == RT_WRAP_CLAMP) return rt_int(rt_min(rt_max(rt_float(i), 0.0f), rt_float(size - 1)));
    if (mode == RT_WRAP_MIRROR) {
        int period = rt_wrap_repeat(i, 2 * size);
        return period < size ? period : 2 * size - 1 - period;
    }
    return rt_wrap_repeat(i, size);
}

RT_FUNC float4 rt_texel(KernelGlobals kg, TextureInfo info, int x, int y, uint sampling) {
    int width = rt_int(info.width);
    int height = rt_int(info.height);
    int wx = rt_wrap(x, width, sampling & 3u);
    int wy = rt_wrap(y, height, (sampling >> 2u) & 3u);
    uint offset = info.first_texel + rt_uint(wy * width + wx);
    return rt_decode_texel(RT_FETCH(kg, texels, offset), info.encoding);
}

// Bilinear (or nearest with RT_SAMPLER_NEAREST) with the sampler's wrap modes (RT_SAMPLER_REPEAT: repeat both
// ways); uv (0, 0) is the top-left corner of the image (glTF convention; loaders convert). Mipmaps are not built:
// a minification filter counts as its base filter.
RT_FUNC float4 rt_sample_texture(KernelGlobals kg, uint texture, float2 uv, uint sampling) {
    TextureInfo info = RT_FETCH(kg, texture_infos, texture);
    float x = uv.x * rt_float(info.width) - 0.5f;
    float y = uv.y * rt_float(info.height) - 0.5f;
    if (!(rt_abs(x) < 1e8f && rt_abs(y) < 1e8f)) return make_float4(0.0f, 0.0f, 0.0f, 1.0f);  // NaN or huge uv
    if ((sampling & RT_SAMPLER_NEAREST) != 0u)
        return rt_texel(kg, info, rt_int(rt_floor(x + 0.5f)), rt_int(rt_floor(y + 0.5f)), sampling);
    float fx = rt_floor(x);
    float fy = rt_floor(y);
    float ax = x - fx;
    float ay = y - fy;
    int x0 = rt_int(fx);
    int y0 = rt_int(fy);
    float4 c00 = rt_texel(kg, info, x0, y0, sampling);
    float4 c10 = rt_texel(kg, info, x0 + 1, y0, sampling);
    float4 c01 = rt_texel(kg, info, x0, y0 + 1, sampling);
    float4 c11 = rt_texel(kg, info, x0 + 1, y0 + 1, sampling);
    float4 top = c00 * (1.0f - ax) + c10 * ax;
    float4 bottom = c01 * (1.0f - ax) + c11 * ax;
    return top * (1.0f - ay) + bottom * ay;
}

#endif
