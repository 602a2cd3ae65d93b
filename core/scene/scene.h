// The host-side scene model every loader produces and every backend consumes (after flattening).
// Plain data: loaders fill it, scene_validate.h checks it, scene_flatten.h turns it into kernels/ arrays.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene/node_animation.h"

namespace prism {

// A triangle mesh in object space. Attribute arrays are either empty or as long as `positions`.
struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;            // empty: flat (geometric) normals
    std::vector<glm::vec2> uv0;                // TEXCOORD_0
    std::vector<glm::vec2> uv1;                // TEXCOORD_1
    std::vector<glm::vec4> colors;             // COLOR_0 / PLY colours, linear RGBA
    std::vector<glm::vec4> tangents;           // TANGENT: xyz along +u, w = bitangent sign (normal maps need them)
    std::vector<glm::uvec3> triangles;         // indices into positions, in file order after triangulation
    std::vector<uint32_t> triangle_materials;  // one material index per triangle
};

// One placement of a mesh. The transform is rigid-or-affine object-to-world.
inline constexpr uint32_t kNoMaterialOverride = 0xffffffffu;

struct Instance {
    uint32_t mesh = 0;
    glm::mat4 transform{1.0f};
    std::string name;
    // Every triangle of this instance uses this material instead of its own (a scene file's per-object material):
    // the mesh, its vertices and its BVH stay shared with the other instances.
    uint32_t material_override = kNoMaterialOverride;
};

// The seed's texture environment modes (thesis Table 1).
enum class TextureMode : uint32_t { Replace = 0, Decal = 1, Modulate = 2, Blend = 3 };

enum class TextureEncoding : uint32_t { Srgb8 = 0, Linear8 = 1, Rgbe = 2 };

struct Texture {
    std::string name;  // file path or a description, for error messages
    int width = 0;
    int height = 0;
    TextureEncoding encoding = TextureEncoding::Srgb8;
    std::vector<uint32_t> texels;  // packed RGBA8 (r in the low byte) or RGBE, row 0 at the top
};

// How texel coordinates outside the image wrap (glTF sampler wrapS/wrapT).
enum class TextureWrap : uint32_t { Repeat = 0, ClampToEdge = 1, MirroredRepeat = 2 };

// One entry of a material's ordered texture stack (thesis 6.3.1: each layer consumes the previous colour).
struct TextureLayer {
    uint32_t texture = 0;
    TextureMode mode = TextureMode::Modulate;
    glm::vec4 environment_color{0.0f};  // T_e for GL_BLEND
    uint32_t uv_set = 0;                // 0: TEXCOORD_0, 1: TEXCOORD_1
    // KHR_texture_transform as a 2x3 affine matrix applied to (u, v, 1).
    glm::vec3 uv_row0{1.0f, 0.0f, 0.0f};
    glm::vec3 uv_row1{0.0f, 1.0f, 0.0f};
    // The sampler: wrap per axis and nearest-texel instead of bilinear filtering (glTF magFilter NEAREST).
    TextureWrap wrap_u = TextureWrap::Repeat;
    TextureWrap wrap_v = TextureWrap::Repeat;
    bool nearest = false;
};

// Opaque: alpha is ignored. Mask: cut out where alpha < cutoff. Blend: 1 - alpha of the light passes straight
// through (no refraction).
enum class AlphaMode : uint32_t { Opaque = 0, Mask = 1, Blend = 2 };

// The seed's material model (thesis 6.3, eqs. 6.3-6.7): everything is an attenuation in [0, 1] except the IOR,
// the Fresnel power and the thickness.
struct Material {
    std::string name;
    glm::vec3 diffuse{0.8f};
    bool use_vertex_colors = true;       // the mesh's vertex colours multiply `diffuse` (glTF's COLOR_0 rule)...
    bool vertex_colors_replace = false;  // ...or replace it where the mesh has them (the seed's rule)
    glm::vec3 specular{1.0f};            // S: attenuates reflected light
    glm::vec3 ambient{1.0f};             // A: attenuates transmitted light
    float reflectivity = 0.0f;           // r
    float transmittance = 0.0f;          // t
    float fresnel_bias = 1.0f;           // R_f = clamp(bias + scale * (1 + I.N)^power, 0, 1)
    float fresnel_scale = 0.0f;
    float fresnel_power = 5.0f;
    glm::vec3 ior{1.5f};         // per channel: different values give chromatic dispersion
    float thickness = 0.0f;      // > 0: thin shell of this thickness (thesis 6.3.4); 0: solid
    glm::vec3 absorption{0.0f};  // solid media: Beer-Lambert coefficients per unit length (glTF volume)
    glm::vec3 emissive{0.0f};
    std::vector<TextureLayer> textures;

    // glTF metallic-roughness (kernels/material.h rt_surface_terms): when set, the kernel derives reflectivity
    // and the specular tint per hit from metallic/roughness (times their texture), and `specular` is the
    // dielectric's specular colour; the seed's loaders leave it off and set reflectivity themselves.
    bool metal_rough = false;
    float metallic = 0.0f;
    float roughness = 1.0f;
    float occlusion_strength = 1.0f;
    float normal_scale = 1.0f;  // glTF normalTexture.scale: multiplies the map's x and y
    // glTF alphaMode (kernels/material.h rt_coverage): alpha = `alpha` x the texture stack's alpha x vertex alpha.
    AlphaMode alpha_mode = AlphaMode::Opaque;
    float alpha = 1.0f;
    float alpha_cutoff = 0.5f;  // Mask: the surface is there where alpha >= this
    // glTF doubleSided false: the back of a surface that does not refract is not seen (a rasterizer culls it) and the
    // ray passes on; a refracting one keeps its back faces, through which a ray inside it leaves.
    bool double_sided = true;
    // Single-purpose maps, each read with its own uv set and transform; `mode` and `environment_color` unused.
    std::optional<TextureLayer> metal_rough_map;     // linear: B = metallic, G = roughness
    std::optional<TextureLayer> emissive_map;        // sRGB: multiplies `emissive`
    std::optional<TextureLayer> occlusion_map;       // linear: R darkens the ambient term
    std::optional<TextureLayer> normal_map;          // linear tangent-space normals
    std::optional<TextureLayer> specular_map;        // linear: A scales the Fresnel term (KHR_materials_specular)
    std::optional<TextureLayer> specular_color_map;  // sRGB: tints the dielectric reflection

    // glTF KHR_materials_iridescence (metal_rough materials): a thin film on the surface whose interference tints
    // the reflection by view angle and thickness (kernels/iridescence.h). A factor of 0 is no film.
    float iridescence = 0.0f;
    float iridescence_ior = 1.3f;
    float iridescence_thickness_min = 100.0f;               // nanometres
    float iridescence_thickness_max = 400.0f;               // the thickness where no thickness map is given
    std::optional<TextureLayer> iridescence_map;            // linear: R scales the factor
    std::optional<TextureLayer> iridescence_thickness_map;  // linear: G picks the thickness in [min, max]

    // glTF KHR_materials_clearcoat (metal_rough materials): a varnish of IOR 1.5 over the surface. 0: none.
    float clearcoat = 0.0f;
    float clearcoat_roughness = 0.0f;
    std::optional<TextureLayer> clearcoat_map;            // linear: R scales the factor
    std::optional<TextureLayer> clearcoat_roughness_map;  // linear: G scales the roughness
};

enum class LightType : uint32_t { Point = 0, Directional = 1, Spot = 2 };

struct Light {
    LightType type = LightType::Point;
    glm::vec3 position{0.0f};                // point and spot lights
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // directional: the direction light travels; spot: the cone's axis
    glm::vec3 color{1.0f};
    float intensity = 1.0f;  // point, spot: candela-like (inverse-square falloff); directional: lux-like
    // Point and spot: the distance where the light has faded to nothing (glTF's window, 1 - (d / range)^4, on
    // top of the inverse square); 0: no range.
    float range = 0.0f;
    // Spot: full light inside the inner angle, none outside the outer one (radians from the axis; glTF's
    // defaults), a smooth falloff between (kernels/types.h, Light.cone).
    float inner_cone = 0.0f;
    float outer_cone = 0.78539816f;
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float vertical_fov_degrees = 45.0f;
};

enum class EnvironmentKind : uint32_t { Constant = 0, CubeMap = 1, Equirect = 2 };

struct Environment {
    EnvironmentKind kind = EnvironmentKind::Constant;
    glm::vec3 color{0.05f};  // Constant: the colour; others: a multiplier
    float intensity = 1.0f;
    // CubeMap: six textures in the order +X (right), -X (left), +Y (up), -Y (down), +Z (front), -Z (back).
    // Equirect: one texture.
    std::vector<uint32_t> textures;
};

// An instance that turns over a sequence (a scene file's "spin", docs/scene-format.md): about `axis` through
// `pivot` (where its placement puts the model's origin), one turn every `seconds`.
struct InstanceSpin {
    uint32_t instance = 0;
    glm::vec3 axis{0.0f, 1.0f, 0.0f};
    glm::vec3 pivot{0.0f};
    float seconds = 1.0f;
};

struct Scene {
    std::string source;  // what was loaded, for messages
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Light> lights;
    Camera camera;
    bool has_camera = false;  // false: frame_scene() places one
    Environment environment;
    glm::vec3 ambient_light{0.1f};  // light that needs no shadow ray (the seed's ambient term)
    std::vector<std::string> warnings;
    std::vector<InstanceSpin> spins;  // instances that move over a sequence (core/scene/scene_motion.h)
    NodeAnimation animation;          // a glTF animation's node transforms, played over a sequence or in the viewer

    size_t triangle_count() const;  // over instances (what is traced)
};

}  // namespace prism
