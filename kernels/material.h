// The seed's material model (thesis 6.3): the diffuse colour from vertex colours, material and an ordered stack
// of textures combined with the OpenGL texture environment modes (Table 1), and the Fresnel approximation
// (eqs. 6.3-6.5). shade.h combines them into the returned colour of eq. 6.7.
#ifndef RT_MATERIAL_H
#define RT_MATERIAL_H

#include "texture.h"

// Thesis Table 1. c = current colour C_c (rgb, a), t = texture colour (T_c, T_a), env = T_e.
RT_FUNC float3 rt_texture_environment(uint mode, float3 c, float4 t, float3 env) {
    float3 tc = rt_xyz(t);
    if (mode == RT_TEXMODE_REPLACE) return tc;
    if (mode == RT_TEXMODE_DECAL) return c * (1.0f - t.w) + tc * t.w;
    if (mode == RT_TEXMODE_BLEND) return c * (rt_splat3(1.0f) - tc) + env * tc;
    return c * tc;   // RT_TEXMODE_MODULATE
}

// Thesis eq. 6.3: R_f = clamp(bias + scale * (1 + I.N)^power, 0, 1), I the unit ray direction and N the unit
// normal facing it (so 1 + I.N runs from 0 head-on to 1 at grazing angles). bias = F0, scale = 1 - F0, power = 5
// is Schlick's approximation.
RT_FUNC float rt_fresnel_reflection(float4 fresnel, float i_dot_n) {
    float x = rt_max(1.0f + i_dot_n, 0.0f);
    return rt_clamp01(fresnel.x + fresnel.y * rt_pow(x, fresnel.z));
}

RT_FUNC float2 rt_apply_uv_transform(TextureLayer layer, float2 uv) {
    float3 h = make_float3(uv.x, uv.y, 1.0f);
    return make_float2(dot(rt_xyz(layer.uv_row0), h), dot(rt_xyz(layer.uv_row1), h));
}

// The diffuse colour C at a surface point: material colour times the interpolated vertex colour (the seed used
// one or the other; with a white material colour this is the seed's rule, and it is glTF's rule for COLOR_0),
// then each texture layer in order, each consuming the previous result (thesis 6.3.1).
RT_FUNC float3 rt_diffuse_color(KernelGlobals kg, Material material, float4 vertex_color, float4 uv) {
    float3 c = rt_xyz(material.diffuse);
    if (material.diffuse.w != 0.0f) c = c * rt_xyz(vertex_color);
    uint first = material.textures.x;
    uint count = material.textures.y;
    for (uint k = 0u; k < count; ++k) {
        TextureLayer layer = RT_FETCH(kg, texture_layers, first + k);
        float2 coords = layer.info.z == 1u ? make_float2(uv.z, uv.w) : make_float2(uv.x, uv.y);
        float4 t = rt_sample_texture(kg, layer.info.x, rt_apply_uv_transform(layer, coords));
        c = rt_texture_environment(layer.info.y, c, t, rt_xyz(layer.environment_color));
    }
    return c;
}

#endif
