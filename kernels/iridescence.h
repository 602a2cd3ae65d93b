// Thin-film interference (KHR_materials_iridescence): a film of another IOR on the surface reflects colours that
// change with the view angle and the film's thickness (soap bubbles, oil, coated lenses). The reflectance is the
// model glTF specifies (Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of
// Varying Iridescence"): the film's two interfaces by Schlick's Fresnel, the first terms of the Airy sum over the
// rays bouncing inside the film, each term's spectrum integrated against the CIE colour matching functions through
// their Gaussian fit, then XYZ to linear Rec. 709 RGB.
#ifndef RT_IRIDESCENCE_H
#define RT_IRIDESCENCE_H

#include "math.h"

// One Airy term's colour for an optical path difference `opd` (nanometres) and phase shifts per channel: the
// Fourier transform of the CIE XYZ matching functions' Gaussian fit (Belcour & Barla's supplement), in Rec. 709.
RT_FUNC float3 rt_thin_film_sensitivity(float opd, float3 shift) {
    float phase = 2.0f * RT_PI * opd * 1.0e-9f;
    float phase2 = phase * phase;
    // exp(-phase^2 var) as exp2; each Gaussian's weight val sqrt(2 pi var), divided by the Y normalisation 1.0685e-7.
    float log2e = 1.44269504f;
    float x = 5.4856e-13f * rt_sqrt(2.0f * RT_PI * 4.3278e9f) * rt_cos(1.6810e6f * phase + shift.x) *
              rt_exp2(-4.3278e9f * phase2 * log2e);
    x = x + 9.7470e-14f * rt_sqrt(2.0f * RT_PI * 4.5282e9f) * rt_cos(2.2399e6f * phase + shift.x) *
                rt_exp2(-4.5282e9f * phase2 * log2e);
    float y = 4.4201e-13f * rt_sqrt(2.0f * RT_PI * 9.3046e9f) * rt_cos(1.7953e6f * phase + shift.y) *
              rt_exp2(-9.3046e9f * phase2 * log2e);
    float z = 5.2481e-13f * rt_sqrt(2.0f * RT_PI * 6.6121e9f) * rt_cos(2.2084e6f * phase + shift.z) *
              rt_exp2(-6.6121e9f * phase2 * log2e);
    float n = 1.0f / 1.0685e-7f;
    x = x * n;
    y = y * n;
    z = z * n;
    return make_float3(3.2404542f * x - 1.5371385f * y - 0.4985314f * z,
                       -0.9692660f * x + 1.8760108f * y + 0.0415560f * z,
                       0.0556434f * x - 0.2040259f * y + 1.0572252f * z);
}

// The base's IOR from its normal-incidence reflectance against air (one channel; a metal's colour gives a fictitious
// one), kept finite.
RT_FUNC float rt_thin_film_base_ior(float f0) {
    float s = rt_sqrt(rt_min(rt_max(f0, 0.0f), 0.9999f));
    return (1.0f + s) / (1.0f - s);
}

// Reflectance (RGB) of a surface of normal-incidence reflectance base_f0 under a film of IOR film_ior and
// `thickness` nanometres, seen from air at cos_theta (> 0). Without a film (thickness 0) it is Schlick's
// reflectance of the base.
RT_FUNC float3 rt_thin_film_fresnel(float film_ior, float cos_theta, float thickness, float3 base_f0) {
    // A film thinner than 0.03 nm fades into air, so a thickness texture reaching 0 shows the bare base.
    float fade = rt_clamp01(thickness / 0.03f);
    float eta = 1.0f + (film_ior - 1.0f) * (fade * fade * (3.0f - 2.0f * fade));
    float sin2_sq = (1.0f / (eta * eta)) * (1.0f - cos_theta * cos_theta);
    float cos2_sq = 1.0f - sin2_sq;
    if (cos2_sq <= 0.0f) return rt_splat3(1.0f);  // total internal reflection in the film
    float cos2 = rt_sqrt(cos2_sq);
    // Air -> film: reflected R12, transmitted twice T121; a phase shift of pi where the film is the rarer medium.
    float r12 = rt_schlick(rt_ior_to_f0(eta, 1.0f), cos_theta);
    float t121 = 1.0f - r12;
    float phi21 = eta < 1.0f ? 0.0f : RT_PI;
    // Film -> base, per channel: Schlick's reflectance at the refracted angle, a phase shift of pi where the base's
    // IOR is below the film's.
    float3 base_ior = make_float3(rt_thin_film_base_ior(base_f0.x), rt_thin_film_base_ior(base_f0.y),
                                  rt_thin_film_base_ior(base_f0.z));
    float3 r23 =
        make_float3(rt_schlick(rt_ior_to_f0(base_ior.x, eta), cos2), rt_schlick(rt_ior_to_f0(base_ior.y, eta), cos2),
                    rt_schlick(rt_ior_to_f0(base_ior.z, eta), cos2));
    float3 phi = make_float3(phi21 + (base_ior.x < eta ? RT_PI : 0.0f), phi21 + (base_ior.y < eta ? RT_PI : 0.0f),
                             phi21 + (base_ior.z < eta ? RT_PI : 0.0f));
    float opd = 2.0f * eta * thickness * cos2;
    // The Airy sum: the directly reflected and once-transmitted light (C0), then two orders of interference.
    float3 r123 = make_float3(rt_min(rt_max(r12 * r23.x, 1e-5f), 0.9999f), rt_min(rt_max(r12 * r23.y, 1e-5f), 0.9999f),
                              rt_min(rt_max(r12 * r23.z, 1e-5f), 0.9999f));
    float3 root = make_float3(rt_sqrt(r123.x), rt_sqrt(r123.y), rt_sqrt(r123.z));
    float3 rs = make_float3(t121 * t121 * r23.x / (1.0f - r123.x), t121 * t121 * r23.y / (1.0f - r123.y),
                            t121 * t121 * r23.z / (1.0f - r123.z));
    float3 reflectance = rt_splat3(r12) + rs;
    float3 cm = rs - rt_splat3(t121);
    for (int m = 1; m <= 2; ++m) {
        cm = cm * root;
        reflectance = reflectance + cm * rt_thin_film_sensitivity(rt_float(m) * opd, phi * rt_float(m)) * 2.0f;
    }
    return rt_max3v(reflectance, rt_splat3(0.0f));
}

#endif
