// Pixel accumulation in 64-bit fixed point built from two 32-bit words (GLSL and OpenCL 1.2 have no 64-bit or
// float atomics everywhere). Integer sums do not depend on the order in which rays finish, so every backend is
// bit-for-bit deterministic run to run, and the wavefront and recursive renderers agree exactly.
#ifndef RT_ACCUMULATE_H
#define RT_ACCUMULATE_H

#include "globals.h"
#include "math.h"

RT_FUNC void rt_accumulate_word_pair(KernelGlobals kg, uint slot, float value) {
    if (!(value > 0.0f)) return;  // nothing to add; also drops NaN
    value = rt_min(value, 1.0e9f);
    // value * 2^24 = high * 2^32 + low: high counts units of 256.
    float high = rt_floor(value * (1.0f / 256.0f));
    float low = rt_min((value - high * 256.0f) * RT_ACCUM_SCALE, 4294967040.0f);
    uint lo = rt_uint(low);
    uint hi = rt_uint(high);
    uint old = RT_ATOMIC_ADD(kg, accum, slot, lo);
    if (old + lo < old) hi += 1u;  // the low word wrapped: carry into the high word
    if (hi != 0u) RT_ATOMIC_ADD(kg, accum, slot + 1u, hi);
}

RT_FUNC void rt_accumulate(KernelGlobals kg, uint pixel, float3 value) {
    uint slot = pixel * RT_ACCUM_WORDS_PER_PIXEL;
    rt_accumulate_word_pair(kg, slot, value.x);
    rt_accumulate_word_pair(kg, slot + 2u, value.y);
    rt_accumulate_word_pair(kg, slot + 4u, value.z);
}

RT_FUNC float rt_accumulated_word_pair(KernelGlobals kg, uint slot) {
    return rt_float(RT_FETCH(kg, accum, slot + 1u)) * 256.0f +
           rt_float(RT_FETCH(kg, accum, slot)) * (1.0f / RT_ACCUM_SCALE);
}

RT_FUNC float3 rt_accumulated(KernelGlobals kg, uint pixel) {
    uint slot = pixel * RT_ACCUM_WORDS_PER_PIXEL;
    return make_float3(rt_accumulated_word_pair(kg, slot), rt_accumulated_word_pair(kg, slot + 2u),
                       rt_accumulated_word_pair(kg, slot + 4u));
}

#endif
