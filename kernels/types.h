// Every struct that lives in a device buffer. Rules (docs/kernels.md): only 16-byte float4/uint4 members and 4-byte
// scalars in rows of four, ids and counts as named members, sizes a multiple of 16, never a bare float3 (12 bytes in
// C++/CUDA, 16 in OpenCL, 16-aligned in GLSL).
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

// Wide layout (the `wide_nodes` array; `nodes` then holds one unused node): 8-ary nodes collapsed from the binary
// SAH tree, the eight child boxes stored per axis (members ending in 0: lanes 0-3, in 1: lanes 4-7; lane k =
// child k), so a traversal tests all eight children with vector arithmetic (one AVX register, or two SSE ones, on
// the cpu backend). Node 0 is the top-level root; a mesh's root is its Instance's root.
//  lower_x0 .. upper_z1: child boxes; an unused (or empty) lane holds +inf in all six, a box the wide slab test
//                        always rejects (its entry distance is +inf or its exit -inf)
//  child0/1 lane k: an interior child: its node index; a leaf: RT_WIDE_LEAF | first << 3 | (count - 1), count
//                   being 1..8 primitives and first the first of them; in the device arrays a mesh leaf's first is
//                   its first TriangleBlock, a top-level leaf's its instance; unused: 0
RT_STRUCT_BEGIN(BvhWideNode)
    float4 lower_x0;
    float4 lower_x1;
    float4 upper_x0;
    float4 upper_x1;
    float4 lower_y0;
    float4 lower_y1;
    float4 upper_y0;
    float4 upper_y1;
    float4 lower_z0;
    float4 lower_z1;
    float4 upper_z0;
    float4 upper_z1;
    uint4 child0;
    uint4 child1;
    uint4 unused0;  // pads the node to 256 bytes: four cache lines
    uint4 unused1;
RT_STRUCT_END(BvhWideNode)

#define RT_BVH_LAYOUT_STACK 0u
#define RT_BVH_LAYOUT_ESCAPE 1u
#define RT_BVH_LAYOUT_WIDE 2u
#define RT_BVH_WIDTH 8u
#define RT_WIDE_LEAF 0x80000000u         // child flag: a leaf, first << 3 | (count - 1) below it
#define RT_WIDE_LEAF_MAX 8u              // primitives per leaf
#define RT_WIDE_FIRST_LIMIT 0x10000000u  // first primitive (block) of a leaf: below 2^28
#define RT_BVH_WIDE_STACK_SIZE 128       // checked against each built tree (core/render/device_scene.cpp)
#define RT_ESCAPE_INTERIOR 0xffffffffu
#define RT_ESCAPE_COUNT_SHIFT 24u
#define RT_ESCAPE_FIRST_MASK 0x00ffffffu
#define RT_BVH_STACK_SIZE 64

// Triangle geometry in BVH leaf order, ready for intersection (v0 and two edges).
//  v0.w = as_float(primitive index within its mesh, in file order); e1.w = rt_edge_scale(e1, e2) (intersect.h);
//  e2.w unused
RT_STRUCT_BEGIN(TriangleGeometry)
    float4 v0;
    float4 e1;
    float4 e2;
RT_STRUCT_END(TriangleGeometry)

// The wide layout's leaves: triangles four to a block, one per lane, as the four-at-a-time test reads them
// (component arrays of v0, e1, e2). A leaf of n triangles owns ceil(n / 4) consecutive blocks; a lane past its end
// has zero edges, which no ray hits. Lane k of slot: the triangle's slot in `triangles` (where shading finds its
// geometric normal), of primitive: its index within its mesh (as TriangleGeometry.v0.w), of instance: the instance
// it belongs to when the instances are flattened (RT_FLAG_FLAT_INSTANCES; the two-level layout shares a mesh's
// blocks among its instances and leaves it RT_NONE); RT_NONE when unused. 192 bytes: three whole cache lines.
RT_STRUCT_BEGIN(TriangleBlock)
    float4 v0x;
    float4 v0y;
    float4 v0z;
    float4 e1x;
    float4 e1y;
    float4 e1z;
    float4 e2x;
    float4 e2y;
    float4 e2z;
    uint4 slot;
    uint4 primitive;
    uint4 instance;
RT_STRUCT_END(TriangleBlock)

// Per-triangle shading data in file order per mesh: its three vertices (global indices into `vertices`) and its
// material.
RT_STRUCT_BEGIN(TriangleShading)
    uint vertex0;
    uint vertex1;
    uint vertex2;
    uint material;
RT_STRUCT_END(TriangleShading)

// Per-vertex shading attributes. normal.w = RT_VERTEX_* bits as a float: whether the mesh has vertex normals (else
// the geometric normal is used) and colours.
RT_STRUCT_BEGIN(Vertex)
    float4 normal;
    float4 color;    // linear RGBA; (1,1,1,1) when the mesh has none
    float4 uv;       // xy = TEXCOORD_0, zw = TEXCOORD_1
    float4 tangent;  // xyz = tangent (along +u), w = bitangent sign (+1/-1); all 0 when the mesh has none
RT_STRUCT_END(Vertex)

// An instance of a mesh (thesis 6.2: the Node Primitive). Rows of 3x4 affine matrices.
RT_STRUCT_BEGIN(Instance)
    float4 world_to_object0;
    float4 world_to_object1;
    float4 world_to_object2;
    float4 object_to_world0;
    float4 object_to_world1;
    float4 object_to_world2;
    uint root;            // root of the mesh's BVH in nodes (in wide_nodes for the wide layout)
    uint first_triangle;  // the mesh's first triangle in triangles
    uint first_shading;   // the mesh's first entry in triangle_shading
    uint flags;           // RT_INSTANCE_* bits
    float4 solid_lower;   // RT_INSTANCE_CLOSED_SOLID: the mesh's bounds in object space (w unused)
    float4 solid_upper;
RT_STRUCT_END(Instance)

#define RT_INSTANCE_MIRRORED 1u  // the transform mirrors (det < 0; informative)
#define RT_INSTANCE_IDENTITY 2u  // world_to_object is exactly the identity: object space is world space
// The mesh bounds a solid (core/scene/closed_solid.h) that rays can enter and every surface of which stops shadow
// rays: a hit on its back lies inside it, where no light outside its bounds is seen (kernels/shade.h).
#define RT_INSTANCE_CLOSED_SOLID 4u

// ---- Materials and textures ----------------------------------------------------------------------------------
// The seed's material (thesis 6.3, eq. 6.7). See core/scene/scene.h Material for the meaning of each field.
//  diffuse.w = 1 to use vertex colours, specular.w = reflectivity r, ambient.w = transmittance t
//  fresnel = (bias, scale, power, thickness), ior.xyz = per-channel IOR, emissive.w = alpha cutoff
//  (RT_MATERIAL_ALPHA_MASK)
// glTF's metallic-roughness model is read when RT_MATERIAL_METAL_ROUGH is set (material.h says how it maps onto
// the seed's terms). The *_map members are texture_layers entries (RT_NONE: none).
RT_STRUCT_BEGIN(Material)
    float4 diffuse;
    float4 specular;
    float4 ambient;
    float4 fresnel;
    float4 ior;
    float4 emissive;
    uint first_layer;  // the base colour's layers: first in texture_layers, and how many
    uint layer_count;
    uint flags;       // RT_MATERIAL_* bits
    float alpha;      // glTF alpha factor
    float metallic;   // metallic factor
    float roughness;  // roughness factor
    float occlusion_strength;
    float normal_scale;
    uint metal_rough_map;  // B = metallic, G = roughness
    uint emissive_map;     // multiplies `emissive`
    uint occlusion_map;    // R
    uint normal_map;
    float4 absorption;               // xyz: Beer-Lambert coefficients per unit length inside a solid medium (0: clear)
    uint specular_map;               // KHR_materials_specular's specularTexture: A scales the Fresnel term
    uint specular_color_map;         // its specularColorTexture: RGB tints it
    uint iridescence_map;            // KHR_materials_iridescence's iridescenceTexture: R scales the factor
    uint iridescence_thickness_map;  // its iridescenceThicknessTexture: G picks the thickness in [min, max]
    float4 iridescence;              // x: factor (0: no film), y: film IOR, z, w: thickness min, max (nanometres)
    float4 clearcoat;                // KHR_materials_clearcoat: x factor (0: no coat), y roughness; z, w unused
    uint clearcoat_map;              // clearcoatTexture: R scales the factor
    uint clearcoat_roughness_map;    // clearcoatRoughnessTexture: G scales the roughness
    uint unused0;
    uint unused1;
RT_STRUCT_END(Material)

#define RT_VERTEX_HAS_NORMAL 1u
#define RT_VERTEX_HAS_COLOR 2u

// The material's reflectivity and specular colour come from glTF metallic/roughness, per hit (textures), in the
// kernel; else they are the seed's constants.
#define RT_MATERIAL_METAL_ROUGH 1u
// glTF alphaMode: MASK cuts the surface out where alpha < the cutoff (emissive.w); BLEND lets 1 - alpha of the
// light pass straight through. alpha = the material's alpha factor x base texture alpha x vertex alpha.
#define RT_MATERIAL_ALPHA_MASK 2u
#define RT_MATERIAL_ALPHA_BLEND 4u
// Vertex colours replace the material colour where the mesh has them (the seed's rule) instead of multiplying it.
#define RT_MATERIAL_VERTEX_REPLACE 8u
// glTF doubleSided false: a hit on the back of a surface that does not refract (ambient.w = 0) is passed through.
#define RT_MATERIAL_SINGLE_SIDED 16u

#define RT_TEXMODE_REPLACE 0u
#define RT_TEXMODE_DECAL 1u
#define RT_TEXMODE_MODULATE 2u
#define RT_TEXMODE_BLEND 3u

// uv_row0/1 = KHR_texture_transform affine rows (xyz)
RT_STRUCT_BEGIN(TextureLayer)
    uint texture_index;
    uint mode;      // RT_TEXMODE_*
    uint uv_set;    // 0: TEXCOORD_0, 1: TEXCOORD_1
    uint sampling;  // RT_WRAP_* of u in bits 0-1, of v in bits 2-3, RT_SAMPLER_NEAREST
    float4 environment_color;
    float4 uv_row0;
    float4 uv_row1;
RT_STRUCT_END(TextureLayer)

#define RT_WRAP_REPEAT 0u
#define RT_WRAP_CLAMP 1u
#define RT_WRAP_MIRROR 2u
#define RT_SAMPLER_NEAREST 16u
#define RT_SAMPLER_REPEAT 0u  // bilinear, repeat both ways

#define RT_TEXENC_SRGB8 0u
#define RT_TEXENC_LINEAR8 1u
#define RT_TEXENC_RGBE 2u

RT_STRUCT_BEGIN(TextureInfo)
    uint first_texel;  // in texels
    uint width;
    uint height;
    uint encoding;  // RT_TEXENC_*
RT_STRUCT_END(TextureInfo)

// ---- Lights and frame ----------------------------------------------------------------------------------------
#define RT_LIGHT_POINT_CODE 0.0f
#define RT_LIGHT_DIRECTIONAL_CODE 1.0f
#define RT_LIGHT_SPOT_CODE 2.0f

// position.xyz (point, spot) or direction.xyz (directional, the way light travels), position.w = the type as a
// float (RT_LIGHT_*_CODE: a plain number, so no bit pattern has to survive a float load);
// color.xyz = colour * intensity, color.w = 1 / range (glTF's distance cutoff; 0: none);
// cone: a spot's falloff as glTF's reference code computes it, clamp(dot(axis, -to_light) * scale + offset)^2, with
// xyz = axis * scale (the axis the way the light travels) and w = offset; (0, 0, 0, 1) for point lights (no cone).
RT_STRUCT_BEGIN(Light)
    float4 position;
    float4 color;
    float4 cone;
RT_STRUCT_END(Light)

#define RT_ENV_CONSTANT 0u
#define RT_ENV_CUBEMAP 1u
#define RT_ENV_EQUIRECT 2u

#define RT_MAX_DEPTH 16u

// Counter slots in the `counters` array (all zeroed at the start of a frame).
#define RT_COUNTER_RAYS 0u                                           // + depth: rays queued for that depth
#define RT_COUNTER_SHADOWS (RT_COUNTER_RAYS + RT_MAX_DEPTH + 1u)     // + depth: shadow rays made at that depth
#define RT_COUNTER_DROPPED (RT_COUNTER_SHADOWS + RT_MAX_DEPTH + 1u)  // rays lost to a full queue (must stay 0)
// + depth: the next ray (shadow ray) of that depth for a traversal stage to take (RT_WORK_LOOP, kernels/stages.h)
#define RT_COUNTER_TAKEN_RAYS (RT_COUNTER_DROPPED + 1u)
#define RT_COUNTER_TAKEN_SHADOWS (RT_COUNTER_TAKEN_RAYS + RT_MAX_DEPTH + 1u)
#define RT_COUNTER_SLOTS (RT_COUNTER_TAKEN_SHADOWS + RT_MAX_DEPTH + 1u)

#define RT_FLAG_ANY_HIT 1u       // a ray query for any hit (--any-hit): the occlude stage runs, not intersect
#define RT_FLAG_NO_SHADING 2u    // ray queries: no frame, intersect only
#define RT_FLAG_ONE_INSTANCE 4u  // the top level holds exactly instance 0 (the wide traversal starts inside it)
// The wide layout with its instances flattened (static scenes, core/render/device_scene_flat.cpp): wide_nodes hold one
// world-space BVH over every instance's triangles, and each block lane names its instance.
#define RT_FLAG_FLAT_INSTANCES 8u
// Some material is cut out or blended (glTF alphaMode MASK/BLEND): the shadow_layers stage traces the shadow rays,
// looking at what they hit (rt_light_through_layers), instead of the shadow stage's one any-hit query.
#define RT_FLAG_ALPHA_SHADOWS 16u
// The resolve stage tone-maps the image with Khronos PBR Neutral (kernels/display.h); without it, values clip at 1.
#define RT_FLAG_TONE_MAP_NEUTRAL 32u
// One instance in the stack layout: the traversal stages' one-mesh variants (intersect_mesh, occlude_mesh) trace
// the rays with a walk that has no instance to enter or leave, which needs fewer registers (more warps fit), and
// the general stages return at once. RT_FLAG_ANY_HIT_MESH_WALK: both bits, occlude_mesh's.
#define RT_FLAG_MESH_WALK 64u
#define RT_FLAG_ANY_HIT_MESH_WALK (RT_FLAG_ANY_HIT | RT_FLAG_MESH_WALK)

// One per frame (array of one element). The camera basis is precomputed on the host (xyz; w unused).
RT_STRUCT_BEGIN(FrameParams)
    float4 camera_position;
    float4 camera_forward;
    float4 camera_right;
    float4 camera_up;
    float4 environment;    // xyz: constant colour or multiplier
    float4 ambient_light;  // xyz
    float tan_half_fov;    // tan(vertical fov / 2)
    float aspect;          // width / height
    float environment_intensity;
    float min_weight;  // the smallest ray weight still traced (Hall's adaptive depth control)
    uint width;
    uint height;
    uint max_depth;
    uint light_count;
    uint environment_kind;     // RT_ENV_*
    uint environment_texture;  // its first texture
    uint ray_capacity;         // rays per depth the queue holds
    uint shadow_capacity;      // shadow rays per depth
    uint instance_count;
    uint bvh_layout;  // RT_BVH_LAYOUT_*
    uint flags;       // RT_FLAG_*
    float exposure;   // the resolve stage's scale of the frame's light, 2^EV (1: none)
    // The pixel rectangle this launch renders: its top-left pixel and size (the whole image unless a frame is split
    // into tiles over devices or ranks). Queues, accumulation and the image are sized for the rectangle; the camera
    // still spans width x height, so a tile's pixels are bit-identical to the whole frame's.
    uint tile_x;
    uint tile_y;
    uint tile_width;
    uint tile_height;
RT_STRUCT_END(FrameParams)

// ---- Queues --------------------------------------------------------------------------------------------------
#define RT_CHANNEL_ALL 7u

// origin.w = tmin, direction.w = tmax (a ray's interval beside its line), weight.xyz = RGB throughput (thesis eqs.
// 6.31/6.32)
RT_STRUCT_BEGIN(Ray)
    float4 origin;
    float4 direction;
    float4 weight;
    uint pixel;
    uint channels;  // RT_CHANNEL_ALL (white), or 1, 2, 4: one channel after dispersion
    uint depth;
    uint unused;
RT_STRUCT_END(Ray)

// tuv = (t, u, v, unused): t = +inf on a miss; u, v = barycentric weights of the second and third vertex
RT_STRUCT_BEGIN(Hit)
    float4 tuv;
    uint instance;
    uint primitive;  // within its mesh, in file order
    uint slot;       // in `triangles` (where shading finds the geometric normal)
    uint unused;
RT_STRUCT_END(Hit)

// A shadow ray carries the light it would deliver to its pixel (contribution.xyz; contribution.w = 0 when it
// delivers nothing and is not traced); direction.w = the distance to the light.
RT_STRUCT_BEGIN(ShadowRay)
    float4 origin;
    float4 direction;
    float4 contribution;
    uint pixel;
    uint unused0;
    uint unused1;
    uint unused2;
RT_STRUCT_END(ShadowRay)

// Pixels accumulate in 64-bit fixed point (two uints per channel, carries propagated with an atomic) so the
// sum is exact and independent of the order rays finish: every backend gives bit-identical images run to run.
#define RT_ACCUM_SCALE 16777216.0f   // 2^24: 6e-8 resolution, 2^40 range
#define RT_ACCUM_WORDS_PER_PIXEL 6u  // r lo, r hi, g lo, g hi, b lo, b hi

#endif
