// What a ray that leaves the scene sees (thesis 6.3: the cube map; Prism adds equirectangular HDR maps).
#ifndef RT_ENVIRONMENT_H
#define RT_ENVIRONMENT_H

#include "texture.h"

// Cube-map face and coordinates with OpenGL's conventions (faces +X, -X, +Y, -Y, +Z, -Z).
RT_FUNC float3 rt_cubemap_lookup(float3 d) {
    float ax = rt_abs(d.x);
    float ay = rt_abs(d.y);
    float az = rt_abs(d.z);
    float face;
    float sc;
    float tc;
    float ma;
    if (ax >= ay && ax >= az) {
        face = d.x > 0.0f ? 0.0f : 1.0f;
        sc = d.x > 0.0f ? -d.z : d.z;
        tc = -d.y;
        ma = ax;
    } else if (ay >= az) {
        face = d.y > 0.0f ? 2.0f : 3.0f;
        sc = d.x;
        tc = d.y > 0.0f ? d.z : -d.z;
        ma = ay;
    } else {
        face = d.z > 0.0f ? 4.0f : 5.0f;
        sc = d.z > 0.0f ? d.x : -d.x;
        tc = -d.y;
        ma = az;
    }
    return make_float3(face, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f));
}

RT_FUNC float3 rt_environment(KernelGlobals kg, float3 direction) {
    FrameParams frame = RT_FETCH(kg, frame, 0u);
    float3 tint = rt_xyz(frame.environment) * frame.environment_intensity;
    uint kind = frame.environment_kind;
    if (kind == RT_ENV_CUBEMAP) {
        float3 f = rt_cubemap_lookup(direction);
        return rt_xyz(rt_sample_texture(kg, frame.environment_texture + rt_uint(f.x), make_float2(f.y, f.z),
                                        RT_SAMPLER_REPEAT)) *
               tint;
    }
    if (kind == RT_ENV_EQUIRECT) {
        float3 d = normalize(direction);
        float u = 0.5f + rt_atan2(d.x, -d.z) * (0.5f / RT_PI);
        float v = rt_acos(rt_min(rt_max(d.y, -1.0f), 1.0f)) * (1.0f / RT_PI);
        return rt_xyz(rt_sample_texture(kg, frame.environment_texture, make_float2(u, v), RT_SAMPLER_REPEAT)) * tint;
    }
    return tint;
}

#endif
