// The seed's material model (thesis 6.3): the diffuse colour from vertex colours, material and an ordered stack
// of textures combined with the OpenGL texture environment modes (Table 1), and the Fresnel approximation
// (eqs. 6.3-6.5). shade.h combines them into the returned colour of eq. 6.7.
#ifndef RT_MATERIAL_H
#define RT_MATERIAL_H

#include "iridescence.h"
#include "texture.h"

// Thesis Table 1. c = current colour C_c (rgb, a), t = texture colour (T_c, T_a), env = T_e.
RT_FUNC float3 rt_texture_environment(uint mode, float3 c, float4 t, float3 env) {
    float3 tc = rt_xyz(t);
    if (mode == RT_TEXMODE_REPLACE) return tc;
    if (mode == RT_TEXMODE_DECAL) return c * (1.0f - t.w) + tc * t.w;
    if (mode == RT_TEXMODE_BLEND) return c * (rt_splat3(1.0f) - tc) + env * tc;
    return c * tc;  // RT_TEXMODE_MODULATE
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

// The texture of one texture_layers entry at a surface point: its uv set, its KHR_texture_transform.
RT_FUNC float4 rt_sample_layer(KernelGlobals kg, TextureLayer layer, float4 uv) {
    float2 coords = layer.uv_set == 1u ? make_float2(uv.z, uv.w) : make_float2(uv.x, uv.y);
    return rt_sample_texture(kg, layer.texture_index, rt_apply_uv_transform(layer, coords), layer.sampling);
}

// The diffuse colour C at a surface point: the material colour and the interpolated vertex colour, then each
// texture layer in order, each consuming the previous result (thesis 6.3.1). Vertex colours multiply the material
// colour (glTF's rule for COLOR_0), or, with RT_MATERIAL_VERTEX_REPLACE, replace it where the mesh has them (the
// seed's rule, which a scene file asks for).
RT_FUNC float3 rt_diffuse_color(KernelGlobals kg, Material material, float4 vertex_color, float4 uv, bool has_colors) {
    float3 c = rt_xyz(material.diffuse);
    if (material.diffuse.w != 0.0f) {
        bool replace = (material.flags & RT_MATERIAL_VERTEX_REPLACE) != 0u;
        c = replace ? (has_colors ? rt_xyz(vertex_color) : c) : c * rt_xyz(vertex_color);
    }
    uint first = material.first_layer;
    uint count = material.layer_count;
    for (uint k = 0u; k < count; ++k) {
        TextureLayer layer = RT_FETCH(kg, texture_layers, first + k);
        float4 t = rt_sample_layer(kg, layer, uv);
        c = rt_texture_environment(layer.mode, c, t, rt_xyz(layer.environment_color));
    }
    return c;
}

// How much of the surface is there (glTF alphaMode): 1 for opaque materials; MASK gives 0 or 1 against the cutoff,
// BLEND the alpha itself. Alpha is the factor times the texture stack's alpha (modulated) times the vertex alpha.
RT_FUNC float rt_coverage(KernelGlobals kg, Material material, float4 vertex_color, float4 uv) {
    uint flags = material.flags;
    if ((flags & (RT_MATERIAL_ALPHA_MASK | RT_MATERIAL_ALPHA_BLEND)) == 0u) return 1.0f;
    float alpha = material.alpha;
    if (material.diffuse.w != 0.0f) alpha = alpha * vertex_color.w;
    for (uint k = 0u; k < material.layer_count; ++k) {
        TextureLayer layer = RT_FETCH(kg, texture_layers, material.first_layer + k);
        alpha = alpha * rt_sample_layer(kg, layer, uv).w;
    }
    if ((flags & RT_MATERIAL_ALPHA_MASK) != 0u) return alpha >= material.emissive.w ? 1.0f : 0.0f;
    return rt_clamp01(alpha);
}

// One of a material's single-purpose maps (Material.maps), or `fallback` where it has none.
RT_FUNC float4 rt_sample_map(KernelGlobals kg, uint layer, float4 uv, float4 fallback) {
    if (layer == RT_NONE) return fallback;
    return rt_sample_layer(kg, RT_FETCH(kg, texture_layers, layer), uv);
}

// What a hit's material gives besides its diffuse colour, where textures and the view angle can vary it.
RT_STRUCT_BEGIN(SurfaceTerms)
    float4 specular;  // xyz: S (tints reflected light), w: reflectivity r
    float4 emission;  // xyz: emitted radiance, w: ambient occlusion (1: none)
    float4 fresnel;   // x: R_f (eq. 6.3), the share of eq. 6.7's reflected path; y: transmittance t at this hit
RT_STRUCT_END(SurfaceTerms)

// glTF metallic-roughness on the seed's model, per hit. A Whitted tracer has no glossy lobe, so roughness dims
// the mirror reflection by gloss = 1 - roughness / 2 and the rest is diffuse. An opaque surface mixes a metal
// (reflects gloss x its base colour at every angle) with a dielectric (reflects gloss x F x its specular colour,
// F = Schlick's Fresnel from the material's F0, so it mirrors the sky at grazing angles); eq. 6.7 with R_f = 1,
// r = metallic gloss + (1 - metallic) gloss F and S = (reflected colour) / r gives exactly that, with
// C (1 - r) left for the diffuse term. Transmissive materials keep the seed's split (r = 1, R_f from the
// Fresnel term), transmitting transmission x (1 - metallic) and mirroring metallic + (1 - metallic) F. Emission is the
// emissive factor times its texture; occlusion (glTF: 1 + strength (texel - 1)) darkens only the ambient term, the one
// light with no shadow ray.
// A thin film (KHR_materials_iridescence, factor k) replaces, by k, the dielectric's Fresnel term with the film's
// reflectance over the dielectric's F0 and the metal's colour with the film's over the base colour as F0, per
// channel (kernels/iridescence.h): the colours go into S, the channels' mean into r or R_f, so the diffuse and
// transmitted shares stay the seed's scalars. Without a film the terms are computed as they were, bit for bit.
// A clear coat (KHR_materials_clearcoat, factor c) is a varnish of IOR 1.5 over all of it: it reflects
// c x Schlick(0.04) of the light uncoloured, dimmed by its own roughness as the base is by its, and the layers
// beneath get the rest: r (or R_f) = coat + (1 - c F) x base, S the two reflections' mix.
RT_FUNC SurfaceTerms rt_surface_terms(KernelGlobals kg, Material m, float3 color, float4 uv, float i_dot_n) {
    SurfaceTerms terms;
    float4 white = make_float4(1.0f, 1.0f, 1.0f, 1.0f);
    // KHR_materials_specular's textures: A scales the whole Fresnel term, RGB tints the dielectric reflection.
    float specular_texel = rt_sample_map(kg, m.specular_map, uv, white).w;
    float3 specular_tint = rt_xyz(rt_sample_map(kg, m.specular_color_map, uv, white));
    terms.specular = rt_float4(rt_xyz(m.specular) * specular_tint, m.specular.w);
    terms.fresnel = make_float4(rt_fresnel_reflection(m.fresnel, i_dot_n) * specular_texel, m.ambient.w, 0.0f, 0.0f);
    terms.emission = rt_float4(rt_xyz(m.emissive) * rt_xyz(rt_sample_map(kg, m.emissive_map, uv, white)), 1.0f);
    if ((m.flags & RT_MATERIAL_METAL_ROUGH) != 0u) {
        float4 texel = rt_sample_map(kg, m.metal_rough_map, uv, white);
        float metallic = m.metallic * texel.z;
        float gloss = 1.0f - 0.5f * (m.roughness * texel.y);
        float film = m.iridescence.x * rt_sample_map(kg, m.iridescence_map, uv, white).x;
        float3 metal_color = color;
        if (film > 0.0f) {
            // Without a thickness map the sample is white: the maximum, as glTF says.
            float g = rt_sample_map(kg, m.iridescence_thickness_map, uv, white).y;
            float thickness = m.iridescence.z + (m.iridescence.w - m.iridescence.z) * g;
            float cos_theta = rt_min(rt_abs(i_dot_n), 1.0f);
            // The dielectric: the film over F0 (the Schlick bias), scaled by KHR_materials_specular's texture as
            // the plain term is.
            float3 dielectric_film =
                rt_thin_film_fresnel(m.iridescence.y, cos_theta, thickness, rt_splat3(m.fresnel.x)) * specular_texel;
            float3 dielectric = rt_lerp3(rt_xyz(terms.specular) * terms.fresnel.x, dielectric_film, film);
            float mean = (dielectric.x + dielectric.y + dielectric.z) * (1.0f / 3.0f);
            terms.specular = rt_float4(mean > 0.0f ? dielectric * (1.0f / mean) : rt_xyz(terms.specular), m.specular.w);
            terms.fresnel.x = mean;
            // The metal's film only where there is metal: with metallic 0 its colour is weighted by 0 below.
            if (metallic > 0.0f)
                metal_color = rt_lerp3(color, rt_thin_film_fresnel(m.iridescence.y, cos_theta, thickness, color), film);
        }
        if (m.ambient.w > 0.0f) {
            terms.specular = rt_float4(rt_lerp3(rt_xyz(terms.specular), metal_color, metallic), m.specular.w);
            // glTF: a metal does not transmit; it mirrors at every angle
            terms.fresnel.x = terms.fresnel.x + metallic * (1.0f - terms.fresnel.x);
            terms.fresnel.y = m.ambient.w * (1.0f - metallic);
        } else {
            float dielectric = (1.0f - metallic) * gloss * terms.fresnel.x;
            float3 reflected = metal_color * (metallic * gloss) + rt_xyz(terms.specular) * dielectric;
            float r = metallic * gloss + dielectric;
            terms.specular = rt_float4(r > 0.0f ? reflected * (1.0f / r) : rt_xyz(terms.specular), r);
            terms.fresnel.x = 1.0f;
        }
        float coat = m.clearcoat.x * rt_sample_map(kg, m.clearcoat_map, uv, white).x;
        if (coat > 0.0f) {
            float coat_f = coat * rt_schlick(0.04f, rt_min(rt_abs(i_dot_n), 1.0f));
            float coat_gloss =
                1.0f - 0.5f * (m.clearcoat.y * rt_sample_map(kg, m.clearcoat_roughness_map, uv, white).y);
            // A transmissive base keeps r = 1 and splits by R_f: the coat adds to R_f (its roughness is not seen).
            bool split = m.ambient.w > 0.0f;
            float base = (split ? terms.fresnel.x : terms.specular.w) * (1.0f - coat_f);
            float coat_reflects = split ? coat_f : coat_f * coat_gloss;
            float total = base + coat_reflects;
            float3 tint = (rt_xyz(terms.specular) * base + rt_splat3(coat_reflects)) * (1.0f / total);
            terms.specular = rt_float4(tint, split ? terms.specular.w : total);
            if (split) terms.fresnel.x = total;
        }
        float occlusion = rt_sample_map(kg, m.occlusion_map, uv, white).x;
        terms.emission.w = 1.0f + m.occlusion_strength * (occlusion - 1.0f);
    }
    return terms;
}

#endif
