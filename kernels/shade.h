// What one ray-surface hit contributes and which rays it spawns (thesis eq. 6.7 unrolled for the wavefront,
// eqs. 6.31/6.32). The wavefront `shade` stage and the recursive reference renderer both call rt_shade, so they
// differ only in how rays are scheduled.
//
// For a hit with colour C, Fresnel R_f/T_f, reflectivity r, transmittance t, specular S, ambient A and ray
// weight W, eq. 6.7 R = R_f (C(1-r) + C_r S r) + T_f (C(1-t) + C_t A t) becomes:
//   local colour:      W * (R_f (1-r) + T_f (1-t)) * C * (ambient light + sum of visible lights) + W * emission
//   reflection ray:    weight W * R_f * S * r          (eq. 6.31)
//   refraction ray(s): weight W * T_f * A * t          (eq. 6.32); a white ray through a dispersive material
//                      becomes three single-channel rays with per-channel IOR (thesis 6.3.5)
// Lights are reached by shadow rays (Whitted); the ambient term needs none.
#ifndef RT_SHADE_H
#define RT_SHADE_H

#include "material.h"

#define RT_MAX_CHILDREN 5  // reflection, three dispersed refractions, the pass-through of a partly covered surface

// The surface at a hit, in world space. Normals face the incoming ray.
RT_STRUCT_BEGIN(Surface)
    float4 position;
    float4 normal;     // shading normal (interpolated vertex normals, or the geometric one)
    float4 geometric;  // geometric normal; w = 1 when the ray arrives from outside (the front side)
    float4 vertex_color;
    float4 uv;  // TEXCOORD_0 in xy, TEXCOORD_1 in zw
    uint material;
    uint has_vertex_color;  // RT_VERTEX_HAS_COLOR when the mesh has vertex colours, else 0
RT_STRUCT_END(Surface)

// `shading_normal` false leaves the shading normal at the geometric one (no vertex normals, no normal map): what a
// shadow ray needs to know of a surface it meets (where it is, its material, uv and vertex colour) costs less.
RT_FUNC Surface rt_surface_at(KernelGlobals kg, float3 direction, Hit hit, bool shading_normal) {
    Instance inst = RT_FETCH(kg, instances, hit.instance);
    TriangleGeometry geometry = RT_FETCH(kg, triangles, hit.slot);
    TriangleShading shading = RT_FETCH(kg, triangle_shading, inst.first_shading + hit.primitive);
    Vertex a = RT_FETCH(kg, vertices, shading.vertex0);
    Vertex b = RT_FETCH(kg, vertices, shading.vertex1);
    Vertex c = RT_FETCH(kg, vertices, shading.vertex2);
    float u = hit.tuv.y;
    float v = hit.tuv.z;
    float w = 1.0f - u - v;

    // Front faces wind counter-clockwise in object space (the glTF loader gives mirrored nodes a re-wound copy),
    // and the inverse transpose keeps an outward normal outward under any transform, mirrors included.
    float3 ng = cross(rt_xyz(geometry.e1), rt_xyz(geometry.e2));
    ng = normalize(rt_transform_normal(inst.world_to_object0, inst.world_to_object1, inst.world_to_object2, ng));
    float3 n = ng;
    uint vertex_flags = rt_uint(a.normal.w);
    if (shading_normal && (vertex_flags & RT_VERTEX_HAS_NORMAL) != 0u) {
        float3 n_object = rt_xyz(a.normal) * w + rt_xyz(b.normal) * u + rt_xyz(c.normal) * v;
        float3 n_world =
            rt_transform_normal(inst.world_to_object0, inst.world_to_object1, inst.world_to_object2, n_object);
        if (dot(n_world, n_world) > 0.0f) n = normalize(n_world);
    }
    // A normal map tilts the shading normal in the frame of the interpolated tangent, bitangent and normal
    // (glTF: tangent along +u, bitangent = cross(normal, tangent) * sign; texel 0.5 is no tilt).
    Material material = RT_FETCH(kg, materials, shading.material);
    if (shading_normal && material.normal_map != RT_NONE && a.tangent.w != 0.0f) {
        float3 t_object = rt_xyz(a.tangent) * w + rt_xyz(b.tangent) * u + rt_xyz(c.tangent) * v;
        float3 t_world =
            rt_transform_vector(inst.object_to_world0, inst.object_to_world1, inst.object_to_world2, t_object);
        t_world = t_world - n * dot(n, t_world);
        if (dot(t_world, t_world) > 0.0f) {
            t_world = normalize(t_world);
            float3 bitangent = cross(n, t_world) * (a.tangent.w < 0.0f ? -1.0f : 1.0f);
            float4 uv4 = a.uv * w + b.uv * u + c.uv * v;
            float4 texel = rt_sample_layer(kg, RT_FETCH(kg, texture_layers, material.normal_map), uv4);
            float scale = material.normal_scale;
            float3 tilt =
                make_float3((2.0f * texel.x - 1.0f) * scale, (2.0f * texel.y - 1.0f) * scale, 2.0f * texel.z - 1.0f);
            float3 mapped = t_world * tilt.x + bitangent * tilt.y + n * tilt.z;
            if (dot(mapped, mapped) > 0.0f) n = normalize(mapped);
        }
    }
    bool front = dot(direction, ng) < 0.0f;
    float3 ng_facing = front ? ng : -ng;
    float3 n_facing = dot(n, ng_facing) < 0.0f ? -n : n;

    // The hit point from the barycentrics on the triangle itself, not origin + t * direction: its error then
    // depends on the triangle's coordinates only, not on how far the ray travelled or how each API rounds t,
    // so the offset of rt_offset_ray_origin always clears the surface (Ray Tracing Gems ch. 6).
    float3 p_object = rt_xyz(geometry.v0) + rt_xyz(geometry.e1) * u + rt_xyz(geometry.e2) * v;
    float3 p_world = rt_transform_point(inst.object_to_world0, inst.object_to_world1, inst.object_to_world2, p_object);

    Surface s;
    s.position = rt_float4(p_world, 0.0f);
    s.normal = rt_float4(n_facing, 0.0f);
    s.geometric = rt_float4(ng_facing, front ? 1.0f : 0.0f);
    s.vertex_color = a.color * w + b.color * u + c.color * v;
    s.uv = a.uv * w + b.uv * u + c.uv * v;
    s.material = shading.material;
    s.has_vertex_color = vertex_flags & RT_VERTEX_HAS_COLOR;
    return s;
}

RT_FUNC Surface rt_surface(KernelGlobals kg, float3 origin, float3 direction, Hit hit) {
    return rt_surface_at(kg, direction, hit, true);
}

// What the shadow rays of a hit need (rt_shadow_ray).
RT_STRUCT_BEGIN(LitPoint)
    float4 light_weight;  // xyz: multiplies each light's irradiance reaching the point (shadow rays)
    float4 origin;        // xyz: the point moved off the surface on the side the ray came from
    float4 normal;        // xyz: shading normal facing the ray
    float4 geometric;     // xyz: geometric normal facing the ray
    uint solid;           // the closed solid (instance) the point lies inside, hit from within; RT_NONE if none
RT_STRUCT_END(LitPoint)

// The child rays go to an array the caller holds, not into this struct: returned by value, a struct with the
// array was copied whole through local memory by NVIDIA's OpenCL (C has no return-value elision; docs/kernels.md,
// "The shade stage's copy").
RT_STRUCT_BEGIN(ShadeResult)
    float4 emitted;  // xyz: what this hit adds to its pixel with no further ray (ambient + emission)
    LitPoint lit;
    uint child_count;  // rays written to the caller's children[0, child_count)
RT_STRUCT_END(ShadeResult)

RT_FUNC Ray rt_make_ray(float3 origin, float3 direction, float3 weight, uint pixel, uint mask, uint depth) {
    Ray r;
    r.origin = rt_float4(origin, 0.0f);
    r.direction = rt_float4(direction, RT_INFINITY);
    r.weight = rt_float4(weight, 0.0f);
    r.pixel = pixel;
    r.channels = mask;
    r.depth = depth;
    r.unused = 0u;
    return r;
}

// The refracted ray of one channel (or of all three when the IOR does not depend on the channel).
// The mirror direction about the shading normal, kept above the surface. Where a normal map (or a smooth normal
// near a silhouette) tilts n far from the geometric normal, the mirror direction can point into the surface;
// mirroring about the geometric normal instead jumped to the flat surface's reflection there, a ring around every
// bump. The direction is laid just above the surface with its bearing kept (Keller et al. 2017, the Iray paper), so
// it joins the mirror directions around it.
RT_FUNC float3 rt_reflect_above(float3 d, float3 n, float3 ng) {
    float3 dir = rt_reflect(d, n);
    float below = dot(dir, ng);
    if (below > 0.0f) return dir;
    float3 along = dir - ng * below;  // the part in the surface's plane
    if (!(dot(along, along) > 1e-12f)) return rt_reflect(d, ng);
    return normalize(normalize(along) + ng * 0.01f);
}

RT_FUNC Ray rt_refraction_ray(Surface s, Material m, float3 d, float3 weight, uint pixel, uint mask, uint depth,
                              uint channel) {
    float3 n = rt_xyz(s.normal);
    float3 ng = rt_xyz(s.geometric);
    float3 outside = rt_offset_ray_origin(rt_xyz(s.position), ng);
    float3 inside = rt_offset_ray_origin(rt_xyz(s.position), -ng);
    float ior = rt_channel(rt_xyz(m.ior), channel);
    float thickness = m.fresnel.w;
    if (thickness > 0.0f) {
        // Thin shell (thesis 6.3.4): the ray travels `thickness` inside along the refracted direction and leaves
        // through a parallel face, so it continues in its original direction, displaced.
        float4 t_in = rt_refract(d, n, 1.0f / ior);
        float3 inward = t_in.w != 0.0f ? rt_xyz(t_in) : d;
        return rt_make_ray(inside + inward * thickness, d, weight, pixel, mask, depth);
    }
    float eta = s.geometric.w != 0.0f ? 1.0f / ior : ior;
    float4 t = rt_refract(d, n, eta);
    if (t.w == 0.0f)
        return rt_make_ray(outside, rt_reflect(d, n), weight, pixel, mask, depth);  // total internal reflection
    float3 dir = normalize(rt_xyz(t));
    // A shading normal far from the geometric one can bend the ray back out; refract about the true surface then.
    if (dot(dir, ng) >= 0.0f) {
        float4 tg = rt_refract(d, ng, eta);
        if (tg.w == 0.0f) return rt_make_ray(outside, rt_reflect(d, ng), weight, pixel, mask, depth);
        dir = normalize(rt_xyz(tg));
    }
    return rt_make_ray(inside, dir, weight, pixel, mask, depth);
}

RT_FUNC ShadeResult rt_shade(KernelGlobals kg, Ray ray, Hit hit, RT_OUT_ARRAY Ray children[RT_MAX_CHILDREN]) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    float3 d = rt_xyz(ray.direction);
    Surface s = rt_surface(kg, rt_xyz(ray.origin), d, hit);
    Material m = RT_FETCH(kg, materials, s.material);
    float3 n = rt_xyz(s.normal);
    float3 ng = rt_xyz(s.geometric);
    // A partly covered surface (alpha) shades with the covered share of the ray's weight; the rest passes on.
    float coverage = rt_coverage(kg, m, s.vertex_color, s.uv);
    // The back of a single-sided surface is not there for the rays that see it (shadow rays still meet it).
    if ((m.flags & RT_MATERIAL_SINGLE_SIDED) != 0u && s.geometric.w == 0.0f && m.ambient.w == 0.0f) coverage = 0.0f;
    float3 arriving = rt_xyz(ray.weight);
    // A ray leaving a solid medium has crossed it from where it entered: Beer-Lambert over that distance.
    if (s.geometric.w == 0.0f && rt_max3(rt_xyz(m.absorption)) > 0.0f) {
        float3 a = rt_xyz(m.absorption) * (-hit.tuv.x * 1.44269504f);  // exp(-x) = 2^(-x log2 e)
        arriving = arriving * make_float3(rt_exp2(a.x), rt_exp2(a.y), rt_exp2(a.z));
    }
    float3 weight = arriving * coverage;
    float3 passing = arriving * (1.0f - coverage);
    uint pixel = ray.pixel;
    uint mask = ray.channels;
    uint depth = ray.depth;

    float3 color = rt_diffuse_color(kg, m, s.vertex_color, s.uv, s.has_vertex_color != 0u);
    SurfaceTerms terms = rt_surface_terms(kg, m, color, s.uv, dot(d, n));
    float reflectivity = terms.specular.w;
    float transmittance = terms.fresnel.y;
    float rf = terms.fresnel.x;
    float tf = 1.0f - rf;
    float3 base = color * (rf * (1.0f - reflectivity) + tf * (1.0f - transmittance));

    ShadeResult result;
    result.lit.light_weight = rt_float4(weight * base, 0.0f);
    result.emitted =
        rt_float4(weight * (base * rt_xyz(frame.ambient_light) * terms.emission.w + rt_xyz(terms.emission)), 0.0f);
    result.lit.origin = rt_float4(rt_offset_ray_origin(rt_xyz(s.position), ng), 0.0f);
    result.lit.normal = s.normal;
    result.lit.geometric = s.geometric;
    bool inside_solid =
        s.geometric.w == 0.0f && (RT_FETCH(kg, instances, hit.instance).flags & RT_INSTANCE_CLOSED_SOLID) != 0u;
    result.lit.solid = inside_solid ? hit.instance : RT_NONE;
    result.child_count = 0u;
    uint count = 0u;
    if (depth + 1u < frame.max_depth) {
        float min_weight = frame.min_weight;
        if (rt_max3(passing) > min_weight) {
            float3 through = rt_offset_ray_origin(rt_xyz(s.position), -ng);
            children[count] = rt_make_ray(through, d, passing, pixel, mask, depth + 1u);
            count += 1u;
        }
        float3 w_reflect = weight * rt_xyz(terms.specular) * (rf * reflectivity);
        if (rt_max3(w_reflect) > min_weight) {
            float3 dir = rt_reflect_above(d, n, ng);
            children[count] = rt_make_ray(rt_xyz(result.lit.origin), dir, w_reflect, pixel, mask, depth + 1u);
            count += 1u;
        }
        float3 w_refract = weight * rt_xyz(m.ambient) * (tf * transmittance);
        if (rt_max3(w_refract) > min_weight) {
            bool dispersive = m.ior.x != m.ior.y || m.ior.y != m.ior.z;
            if (mask == RT_CHANNEL_ALL && dispersive) {
                for (uint c = 0u; c < 3u; ++c) {
                    uint channel_mask = 1u << c;
                    float3 w_channel = rt_mask3(w_refract, channel_mask);
                    if (rt_max3(w_channel) > min_weight) {
                        children[count] = rt_refraction_ray(s, m, d, w_channel, pixel, channel_mask, depth + 1u, c);
                        count += 1u;
                    }
                }
            } else {
                uint channel = mask == 1u ? 0u : (mask == 4u ? 2u : 1u);
                children[count] = rt_refraction_ray(s, m, d, w_refract, pixel, mask, depth + 1u, channel);
                count += 1u;
            }
        }
    }
    result.child_count = count;
    return result;
}

// Whether `light` lies outside the bounds of closed solid `solid` (an instance marked RT_INSTANCE_CLOSED_SOLID): a
// directional light always. Every path from inside a closed surface to a point outside it crosses the surface, and
// every surface of the solid stops shadow rays, so a point inside sees no such light, whatever else the scene holds:
// its shadow ray is not traced (docs/kernels.md, "Shadow rays from inside a solid"). A light inside the bounds (a
// lamp in a glass bulb) is traced as any other.
RT_FUNC bool rt_light_outside_solid(KernelGlobals kg, uint solid, Light light) {
    if (light.position.w == RT_LIGHT_DIRECTIONAL_CODE) return true;
    Instance inst = RT_FETCH(kg, instances, solid);
    float3 p =
        rt_transform_point(inst.world_to_object0, inst.world_to_object1, inst.world_to_object2, rt_xyz(light.position));
    float3 lower = rt_xyz(inst.solid_lower);
    float3 upper = rt_xyz(inst.solid_upper);
    return p.x < lower.x || p.y < lower.y || p.z < lower.z || p.x > upper.x || p.y > upper.y || p.z > upper.z;
}

// The shadow ray towards light `index` and what it delivers if nothing blocks it; contribution.w = 0 when the
// light is behind the surface or the point lies in a closed solid that hides the light (no ray needed).
RT_FUNC ShadowRay rt_shadow_ray(KernelGlobals kg, LitPoint lit, uint index, uint pixel) {
    Light light = RT_FETCH(kg, lights, index);
    float3 origin = rt_xyz(lit.origin);
    float3 to_light;
    float distance;
    float falloff;
    if (light.position.w == RT_LIGHT_DIRECTIONAL_CODE) {
        to_light = -normalize(rt_xyz(light.position));
        distance = RT_INFINITY;
        falloff = 1.0f;
    } else {
        float3 l = rt_xyz(light.position) - origin;
        float d2 = dot(l, l);
        distance = rt_sqrt(d2);
        to_light = l * (1.0f / distance);
        // glTF's window at the light's range, 1 - (d / range)^4 (exactly 1 with no range), and a spot's cone
        // (exactly 1 for a point light): the inverse square's bits are kept wherever neither applies.
        float x2 = d2 * (light.color.w * light.color.w);
        float window = rt_clamp01(1.0f - x2 * x2);
        float cone = rt_clamp01(dot(rt_xyz(light.cone), -to_light) + light.cone.w);
        falloff = window * (cone * cone) / d2;
    }
    // A light below the geometric surface is hidden by the surface itself, whatever the shading normal says;
    // tracing that ray would only find the surface's own neighbours at distances each API rounds differently.
    float cosine = dot(rt_xyz(lit.geometric), to_light) > 0.0f ? dot(rt_xyz(lit.normal), to_light) : 0.0f;
    ShadowRay sr;
    sr.origin = rt_float4(origin, 0.0f);
    sr.direction = rt_float4(to_light, distance);
    float3 contribution = rt_xyz(lit.light_weight) * rt_xyz(light.color) * (rt_max(cosine, 0.0f) * falloff);
    bool hidden = lit.solid != RT_NONE && rt_light_outside_solid(kg, lit.solid, light);
    sr.contribution = rt_float4(contribution, !hidden && cosine > 0.0f && rt_max3(contribution) > 0.0f ? 1.0f : 0.0f);
    sr.pixel = pixel;
    sr.unused0 = 0u;
    sr.unused1 = 0u;
    sr.unused2 = 0u;
    return sr;
}

#endif
