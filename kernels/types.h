// Every struct that lives in a device buffer. Rules (docs/kernels.md): only 4-byte scalars and 16-byte float4/uint4
// members, sizes a multiple of 16, never a bare float3 (12 bytes in C++/CUDA, 16 in OpenCL, 16-aligned in GLSL).
// tests/ checks each struct's size and member offsets in all four languages against layout_table.h.
#ifndef RT_TYPES_H
#define RT_TYPES_H

#include "compat/compat.h"

// ---- BVH -----------------------------------------------------------------------------------------------------
// One node in two 16-byte blocks. Two layouts share the struct (bvh_flatten.cpp writes them, traverse.h reads):
//  stack layout:  lower.w = as_float(first child index, or first primitive), upper.w = as_float(primitive count;
//                 0 for an interior node, whose children sit at first and first + 1)
//  escape layout (the seed's stackless order, thesis 6.4.1): nodes in depth-first order, left child at i + 1;
//                 lower.w = as_float(escape index: where to go when the box is missed or a leaf is done),
//                 upper.w = as_float(leaf: first primitive | count << 24; interior: 0xffffffff)
RT_STRUCT_BEGIN(BvhNode)
    float4 lower;
    float4 upper;
RT_STRUCT_END(BvhNode)

#define RT_BVH_LAYOUT_STACK 0u
#define RT_BVH_LAYOUT_ESCAPE 1u
#define RT_ESCAPE_INTERIOR 0xffffffffu
#define RT_ESCAPE_COUNT_SHIFT 24u
#define RT_ESCAPE_FIRST_MASK 0x00ffffffu
#define RT_BVH_STACK_SIZE 64

// Triangle geometry in BVH leaf order, ready for intersection (v0 and two edges).
//  v0.w = as_float(primitive index within its mesh, in file order); e1.w, e2.w unused
RT_STRUCT_BEGIN(TriangleGeometry)
    float4 v0;
    float4 e1;
    float4 e2;
RT_STRUCT_END(TriangleGeometry)

// Per-triangle shading data in file order per mesh: indices into the vertex arrays.
//  vertices.xyz = global vertex indices, vertices.w = material index
RT_STRUCT_BEGIN(TriangleShading)
    uint4 vertices;
RT_STRUCT_END(TriangleShading)

// Per-vertex shading attributes. normal.w = 1 when the mesh has vertex normals (else the geometric normal is used).
RT_STRUCT_BEGIN(Vertex)
    float4 normal;
    float4 color;   // linear RGBA; (1,1,1,1) when the mesh has none
    float4 uv;      // xy = TEXCOORD_0, zw = TEXCOORD_1
RT_STRUCT_END(Vertex)

// An instance of a mesh (thesis 6.2: the Node Primitive). Rows of 3x4 affine matrices.
//  info.x = root of the mesh's BVH in nodes, info.y = first triangle of the mesh in triangles,
//  info.z = first entry of the mesh in triangle_shading, info.w = 1 if the transform mirrors (det < 0; informative)
RT_STRUCT_BEGIN(Instance)
    float4 world_to_object0;
    float4 world_to_object1;
    float4 world_to_object2;
    float4 object_to_world0;
    float4 object_to_world1;
    float4 object_to_world2;
    uint4 info;
RT_STRUCT_END(Instance)

// ---- Materials and textures ----------------------------------------------------------------------------------
// The seed's material (thesis 6.3, eq. 6.7). See core/scene.h Material for the meaning of each field.
//  diffuse.w = 1 to use vertex colours, specular.w = reflectivity r, ambient.w = transmittance t
//  fresnel = (bias, scale, power, thickness), ior.xyz = per-channel IOR, emissive.w unused
//  textures.x = first layer in texture_layers, textures.y = layer count
RT_STRUCT_BEGIN(Material)
    float4 diffuse;
    float4 specular;
    float4 ambient;
    float4 fresnel;
    float4 ior;
    float4 emissive;
    uint4 textures;
RT_STRUCT_END(Material)

#define RT_TEXMODE_REPLACE 0u
#define RT_TEXMODE_DECAL 1u
#define RT_TEXMODE_MODULATE 2u
#define RT_TEXMODE_BLEND 3u

// info.x = texture index, info.y = mode, info.z = uv set; uv_row0/1 = KHR_texture_transform affine rows (xyz)
RT_STRUCT_BEGIN(TextureLayer)
    uint4 info;
    float4 environment_color;
    float4 uv_row0;
    float4 uv_row1;
RT_STRUCT_END(TextureLayer)

#define RT_TEXENC_SRGB8 0u
#define RT_TEXENC_LINEAR8 1u
#define RT_TEXENC_RGBE 2u

// info.x = first texel in texels, info.y = width, info.z = height, info.w = encoding
RT_STRUCT_BEGIN(TextureInfo)
    uint4 info;
RT_STRUCT_END(TextureInfo)

// ---- Lights and frame ----------------------------------------------------------------------------------------
#define RT_LIGHT_POINT_CODE 0.0f
#define RT_LIGHT_DIRECTIONAL_CODE 1.0f

// position.xyz (point) or direction.xyz (directional, the way light travels), position.w = the type as a float
// (RT_LIGHT_*_CODE: a plain number, so no bit pattern has to survive a float load);
// color.xyz = colour * intensity
RT_STRUCT_BEGIN(Light)
    float4 position;
    float4 color;
RT_STRUCT_END(Light)

#define RT_ENV_CONSTANT 0u
#define RT_ENV_CUBEMAP 1u
#define RT_ENV_EQUIRECT 2u

#define RT_MAX_DEPTH 16u

// Counter slots in the `counters` array (all zeroed at the start of a frame).
#define RT_COUNTER_RAYS 0u                               // + depth: rays queued for that depth
#define RT_COUNTER_SHADOWS (RT_COUNTER_RAYS + RT_MAX_DEPTH + 1u)   // + depth: shadow rays made at that depth
#define RT_COUNTER_DROPPED (RT_COUNTER_SHADOWS + RT_MAX_DEPTH + 1u) // rays lost to a full queue (must stay 0)
#define RT_COUNTER_SLOTS (RT_COUNTER_DROPPED + 1u)

#define RT_FLAG_ANY_HIT 1u        // intersect reports any hit (ray queries with --any-hit)
#define RT_FLAG_NO_SHADING 2u     // ray queries: no frame, intersect only

// One per frame (array of one element). The camera basis is precomputed on the host.
//  camera_position.w = tan(vertical fov / 2), camera_forward.w = aspect ratio
//  environment.xyz = constant colour or multiplier, environment.w = intensity
//  ambient_light.w = the smallest ray weight still traced (Hall's adaptive depth control)
//  size = (width, height, max depth, light count)
//  env = (kind, first texture, queue capacity, shadow queue capacity)
//  scene = (instance count, BVH layout, flags, ray count for queries)
RT_STRUCT_BEGIN(FrameParams)
    float4 camera_position;
    float4 camera_forward;
    float4 camera_right;
    float4 camera_up;
    float4 environment;
    float4 ambient_light;
    uint4 size;
    uint4 env;
    uint4 scene;
RT_STRUCT_END(FrameParams)

// ---- Queues --------------------------------------------------------------------------------------------------
#define RT_CHANNEL_ALL 7u

// origin.w = tmin, direction.w = tmax, weight.xyz = RGB throughput (thesis eqs. 6.31/6.32);
// info.x = pixel, info.y = channel mask (7 = white; 1, 2, 4 = one channel after dispersion), info.z = depth
RT_STRUCT_BEGIN(Ray)
    float4 origin;
    float4 direction;
    float4 weight;
    uint4 info;
RT_STRUCT_END(Ray)

// tuv = (t, u, v, unused): t = +inf on a miss; u, v = barycentric weights of the second and third vertex
// ids = (instance, primitive within its mesh, slot in `triangles` (for the geometric normal), unused)
RT_STRUCT_BEGIN(Hit)
    float4 tuv;
    uint4 ids;
RT_STRUCT_END(Hit)

// A shadow ray carries the light it would deliver: contribution.xyz, info.x = pixel.
RT_STRUCT_BEGIN(ShadowRay)
    float4 origin;
    float4 direction;
    float4 contribution;
    uint4 info;
RT_STRUCT_END(ShadowRay)

// Pixels accumulate in 64-bit fixed point (two uints per channel, carries propagated with an atomic) so the
// sum is exact and independent of the order rays finish: every backend gives bit-identical images run to run.
#define RT_ACCUM_SCALE 16777216.0f   // 2^24: 6e-8 resolution, 2^40 range
#define RT_ACCUM_WORDS_PER_PIXEL 6u  // r lo, r hi, g lo, g hi, b lo, b hi

#endif
