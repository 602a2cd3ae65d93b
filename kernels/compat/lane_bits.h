// Lane masks kept as bits (bit k: lane k), for code that combines several comparisons before it needs the bits:
// the plain-code form of cpu.h's SSE lane masks, for the compat headers and builds without vector registers to keep
// them in (CUDA, OpenCL C, the cpu build without SSE). Included once rt_mask_lt4, rt_mask_le4 and RT_FUNC exist.
#ifndef RT_COMPAT_LANE_BITS_H
#define RT_COMPAT_LANE_BITS_H

#define rt_lanes4 uint
RT_FUNC uint rt_lt_lanes4(float4 a, float4 b) { return rt_mask_lt4(a, b); }
RT_FUNC uint rt_le_lanes4(float4 a, float4 b) { return rt_mask_le4(a, b); }
RT_FUNC uint rt_and_lanes4(uint a, uint b) { return a & b; }
RT_FUNC uint rt_or_lanes4(uint a, uint b) { return a | b; }
RT_FUNC uint rt_andnot_lanes4(uint a, uint b) { return ~a & b; }
RT_FUNC uint rt_lane_bits4(uint m) { return m; }

#endif
