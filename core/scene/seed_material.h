// Shared pieces of the seed's material model (core/scene/scene.h Material): the Fresnel term (thesis eq. 6.3:
// R_f = clamp(bias + scale * (1 + I.N)^power, 0, 1)) for the two kinds of surface every loader produces, and the
// default material. See docs/materials.md.
#pragma once

#include "core/scene/scene.h"

namespace prism {

// Normal-incidence reflectance of a dielectric boundary with air.
inline float schlick_f0(float ior) {
    float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

// Schlick's approximation written in the seed's form: with I.N = -cos(theta), bias + scale * (1 - cos)^5 is
// F0 + (1 - F0) (1 - cos)^5.
inline void set_dielectric_fresnel(Material& material, float f0) {
    material.fresnel_bias = f0;
    material.fresnel_scale = 1.0f - f0;
    material.fresnel_power = 5.0f;
}

// Opaque surfaces: R_f = 1, so eq. 6.7 reduces to C (1 - r) + C_r S r and nothing is transmitted.
inline void set_opaque_fresnel(Material& material) {
    material.fresnel_bias = 1.0f;
    material.fresnel_scale = 0.0f;
    material.fresnel_power = 5.0f;
}

// What a model without materials is drawn with: light grey, matte, opaque.
inline Material default_material() {
    Material material;
    material.name = "default";
    material.diffuse = glm::vec3(0.8f);
    set_opaque_fresnel(material);
    return material;
}

}  // namespace prism
