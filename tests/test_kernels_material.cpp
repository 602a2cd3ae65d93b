// The seed's material formulas (thesis 6.3) in kernels/, against values computed by hand from the equations.
#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>

#include <gtest/gtest.h>

#include "core/render/device_scene.h"
#include "core/render/host_globals.h"
#include "kernels/stages.h"

namespace {

void expect_near3(float3 a, float3 b, float eps = 1e-6f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

}  // namespace

// Eq. 6.3: R_f = clamp(bias + scale * (1 + I.N)^power, 0, 1).
TEST(SeedMaterial, FresnelReflectionEquation63) {
    float4 schlick{0.04f, 0.96f, 5.0f, 0.0f};
    EXPECT_NEAR(rt_fresnel_reflection(schlick, -1.0f), 0.04f, 1e-7f);             // head-on: F0
    EXPECT_NEAR(rt_fresnel_reflection(schlick, -0.5f), 0.07f, 1e-6f);             // 0.04 + 0.96 * 0.5^5
    EXPECT_NEAR(rt_fresnel_reflection(schlick, 0.0f), 1.0f, 1e-7f);               // grazing
    EXPECT_EQ(rt_fresnel_reflection(float4{0.9f, 0.5f, 1.0f, 0}, 0.0f), 1.0f);    // clamped above (eq. 6.4)
    EXPECT_EQ(rt_fresnel_reflection(float4{-0.5f, 0.1f, 1.0f, 0}, -1.0f), 0.0f);  // clamped below
}

// Table 1: the OpenGL texture environment modes.
TEST(SeedMaterial, TextureEnvironmentModesTable1) {
    float3 c{0.2f, 0.4f, 0.6f};
    float4 t{0.5f, 0.5f, 1.0f, 0.25f};
    float3 env{1.0f, 0.0f, 0.0f};
    expect_near3(rt_texture_environment(RT_TEXMODE_REPLACE, c, t, env), {0.5f, 0.5f, 1.0f});
    expect_near3(rt_texture_environment(RT_TEXMODE_DECAL, c, t, env), {0.275f, 0.425f, 0.7f});
    expect_near3(rt_texture_environment(RT_TEXMODE_MODULATE, c, t, env), {0.1f, 0.2f, 0.6f});
    expect_near3(rt_texture_environment(RT_TEXMODE_BLEND, c, t, env), {0.6f, 0.2f, 0.0f});
}

// Eq. 6.9: r = d - 2 (d.n) n with n facing the ray.
TEST(SeedMaterial, ReflectionEquation69) {
    float s = std::sqrt(0.5f);
    expect_near3(rt_reflect(float3{s, -s, 0}, float3{0, 1, 0}), {s, s, 0});
}

// A normal map's tilt can put the mirror direction under the surface: it is laid just above the surface with its
// bearing kept, not mirrored about the geometric normal (which showed the flat surface's reflection in a ring
// around every bump); above the surface the mirror direction is unchanged.
TEST(SeedMaterial, ReflectionUnderTheSurfaceIsLaidJustAboveIt) {
    float3 ng{0, 1, 0};
    float3 d = normalize(float3{0.2f, -1.0f, -0.3f});
    float3 gentle = normalize(float3{0.1f, 1.0f, 0.0f});
    expect_near3(rt_reflect_above(d, gentle, ng), rt_reflect(d, gentle));

    float3 steep = normalize(float3{-1.0f, 0.35f, 0.0f});  // near a bump's silhouette
    float3 mirror = rt_reflect(d, steep);
    ASSERT_LT(dot(mirror, ng), 0.0f) << "the case under test: the mirror direction points into the surface";
    float3 dir = rt_reflect_above(d, steep, ng);
    EXPECT_NEAR(length(dir), 1.0f, 1e-6f);
    EXPECT_GT(dot(dir, ng), 0.0f);
    EXPECT_LT(dot(dir, ng), 0.02f) << "just above the surface, not the flat surface's mirror direction";
    // The same bearing in the surface's plane as the mirror direction.
    float3 bearing = normalize(float3{mirror.x, 0.0f, mirror.z});
    expect_near3(normalize(float3{dir.x, 0.0f, dir.z}), bearing, 1e-5f);
    // Straight into the surface: no bearing to keep, the geometric mirror.
    expect_near3(rt_reflect_above(float3{0, -1, 0}, float3{1, 0, 0}, ng), float3{0, 1, 0});
}

// Eq. 6.30 obeys Snell's law (eq. 6.10) and reports total internal reflection.
TEST(SeedMaterial, RefractionEquation630) {
    float s = std::sqrt(0.5f);
    float4 t = rt_refract(float3{s, -s, 0}, float3{0, 1, 0}, 1.0f / 1.5f);
    ASSERT_EQ(t.w, 1.0f);
    float sin2 = s / 1.5f;
    EXPECT_NEAR(t.x, sin2, 1e-6f);
    EXPECT_NEAR(t.y, -std::sqrt(1.0f - sin2 * sin2), 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-7f);
    // Leaving glass at 60 degrees: 1.5 * sin 60 > 1.
    EXPECT_EQ(rt_refract(float3{std::sin(1.0472f), -std::cos(1.0472f), 0}, float3{0, 1, 0}, 1.5f).w, 0.0f);
    // Head-on rays pass straight.
    float4 straight = rt_refract(float3{0, -1, 0}, float3{0, 1, 0}, 1.0f / 1.5f);
    EXPECT_NEAR(straight.y, -1.0f, 1e-6f);
}

// The cpu backends read 8-bit sRGB texels through a table: the same bits as the formula the GPUs evaluate.
TEST(SeedMaterial, Srgb8TableHoldsTheFormulasValues) {
    for (uint v = 0; v < 256; ++v)
        EXPECT_EQ(std::bit_cast<uint32_t>(rt_srgb8_to_linear(v)),
                  std::bit_cast<uint32_t>(rt_srgb_to_linear(float(v) * (1.0f / 255.0f))))
            << v;
    EXPECT_EQ(rt_srgb8_to_linear(0), 0.0f);
    EXPECT_EQ(rt_srgb8_to_linear(255), 1.0f);
}

TEST(SeedMaterial, SrgbTransferIsExactAtKnownPoints) {
    EXPECT_NEAR(rt_srgb_to_linear(0.5f), 0.2140411f, 1e-6f);
    EXPECT_NEAR(rt_linear_to_srgb(0.2140411f), 0.5f, 1e-6f);
    EXPECT_NEAR(rt_linear_to_srgb(2.0f), 1.0f, 1e-6f);  // clamped
}

namespace {

// One triangle in the z = 0 plane facing +z, with the material under test, hit head-on from +z.
struct OneTriangle {
    prism::DeviceScene device;
    FrameParams frame{};
    KernelGlobals kg{};

    explicit OneTriangle(const prism::Material& material) {
        prism::Scene scene;
        scene.source = "one triangle";
        prism::Mesh mesh;
        mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
        mesh.triangles = {{0, 1, 2}};
        mesh.triangle_materials = {0};
        scene.meshes.push_back(mesh);
        scene.instances.push_back(prism::Instance{0, glm::mat4(1.0f), "triangle"});
        scene.materials.push_back(material);
        scene.ambient_light = glm::vec3(0.1f);
        device = prism::build_device_scene(scene);
        frame.ambient_light = float4{0.1f, 0.1f, 0.1f, 0.0f};
        frame.min_weight = 1e-4f;
        frame.width = frame.height = 1;
        frame.max_depth = 8;
        kg = prism::host_globals(device, &frame);
    }

    // rt_shade's result with the child rays it wrote.
    struct Shaded : ShadeResult {
        Ray children[RT_MAX_CHILDREN];
    };

    Shaded shade_head_on(float3 weight, uint mask) {
        Ray ray = rt_make_ray(float3{0, 0, 2}, float3{0, 0, -1}, weight, 0, mask, 0);
        Hit hit = rt_trace(kg, rt_xyz(ray.origin), rt_xyz(ray.direction), 0.0f, RT_INFINITY, false);
        EXPECT_NEAR(hit.tuv.x, 2.0f, 1e-6f);
        Shaded s;
        static_cast<ShadeResult&>(s) = rt_shade(kg, ray, hit, s.children);
        return s;
    }
};

prism::Material glass() {
    prism::Material m;
    m.diffuse = glm::vec3(0.5f);
    m.reflectivity = 0.3f;
    m.transmittance = 0.6f;
    m.specular = {1.0f, 0.5f, 0.25f};
    m.ambient = {0.2f, 0.4f, 0.8f};
    m.fresnel_bias = 0.1f;
    m.fresnel_scale = 0.9f;
    m.fresnel_power = 5.0f;
    m.ior = {1.4f, 1.5f, 1.6f};
    return m;
}

}  // namespace

// Eq. 6.7 with eqs. 6.31/6.32: head-on, R_f = bias = 0.1, T_f = 0.9.
TEST(SeedMaterial, ShadeWeightsFollowEquation67) {
    OneTriangle scene(glass());
    auto s = scene.shade_head_on(float3{1, 1, 1}, RT_CHANNEL_ALL);
    float base = 0.5f * (0.1f * (1 - 0.3f) + 0.9f * (1 - 0.6f));  // C (R_f (1-r) + T_f (1-t)) = 0.215
    expect_near3(rt_xyz(s.lit.light_weight), {base, base, base});
    expect_near3(rt_xyz(s.emitted), {base * 0.1f, base * 0.1f, base * 0.1f});
    ASSERT_EQ(s.child_count, 4u);  // reflection + three dispersed refractions (thesis 6.3.5)
    expect_near3(rt_xyz(s.children[0].weight), {0.1f * 0.3f * 1.0f, 0.1f * 0.3f * 0.5f, 0.1f * 0.3f * 0.25f});
    expect_near3(rt_xyz(s.children[0].direction), {0, 0, 1});
    expect_near3(rt_xyz(s.children[1].weight), {0.9f * 0.6f * 0.2f, 0, 0});
    expect_near3(rt_xyz(s.children[2].weight), {0, 0.9f * 0.6f * 0.4f, 0});
    expect_near3(rt_xyz(s.children[3].weight), {0, 0, 0.9f * 0.6f * 0.8f});
    EXPECT_EQ(s.children[1].channels, 1u);
    EXPECT_EQ(s.children[2].channels, 2u);
    EXPECT_EQ(s.children[3].channels, 4u);
    EXPECT_EQ(s.children[1].depth, 1u);       // depth + 1
    EXPECT_LT(s.children[1].origin.z, 0.0f);  // refracted rays start below the surface
    EXPECT_GT(s.children[0].origin.z, 0.0f);  // reflected rays above it
}

TEST(SeedMaterial, SingleChannelRaySpawnsOneRefraction) {
    OneTriangle scene(glass());
    auto s = scene.shade_head_on(float3{0, 1, 0}, 2u);
    ASSERT_EQ(s.child_count, 2u);
    expect_near3(rt_xyz(s.children[1].weight), {0, 0.9f * 0.6f * 0.4f, 0});
    EXPECT_EQ(s.children[1].channels, 2u);
}

TEST(SeedMaterial, ThinShellOffsetsAndKeepsDirection) {
    prism::Material m = glass();
    m.ior = glm::vec3(1.5f);
    m.thickness = 0.5f;
    OneTriangle scene(m);
    auto s = scene.shade_head_on(float3{1, 1, 1}, RT_CHANNEL_ALL);
    ASSERT_EQ(s.child_count, 2u);
    expect_near3(rt_xyz(s.children[1].direction), {0, 0, -1});
    EXPECT_NEAR(s.children[1].origin.z, -0.5f, 1e-4f);  // plus the few-ulp self-intersection offset
}

TEST(SeedMaterial, NoChildrenAtMaximumDepth) {
    OneTriangle scene(glass());
    scene.frame.max_depth = 1;
    EXPECT_EQ(scene.shade_head_on(float3{1, 1, 1}, RT_CHANNEL_ALL).child_count, 0u);
}

namespace {

// Linear Rec. 709 RGB, balanced so that a flat spectrum is white, of the reflectance spectrum `reflectance`
// (380-780 nm), through Wyman, Sloan and Shirley's (2013) multi-lobe fit of the CIE 1931 matching functions:
// independent of the Gaussian fit in kernels/iridescence.h.
template <typename Spectrum>
float3 spectrum_rgb(Spectrum reflectance) {
    auto lobe = [](double l, double mean, double below, double above) {
        const double s = l < mean ? below : above;
        return std::exp(-0.5 * (l - mean) * (l - mean) / (s * s));
    };
    double xyz[3] = {0, 0, 0}, white[3] = {0, 0, 0};
    for (double l = 380.0; l <= 780.0; l += 1.0) {
        const double x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) -
                         0.065 * lobe(l, 501.1, 20.4, 26.2);
        const double y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
        const double z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
        const double r = reflectance(l);
        xyz[0] += r * x, xyz[1] += r * y, xyz[2] += r * z;
        white[0] += x, white[1] += y, white[2] += z;
    }
    const double m[3][3] = {
        {3.2404542, -1.5371385, -0.4985314}, {-0.9692660, 1.8760108, 0.0415560}, {0.0556434, -0.2040259, 1.0572252}};
    double rgb[3];
    for (int c = 0; c < 3; ++c) {
        const double value = m[c][0] * xyz[0] + m[c][1] * xyz[1] + m[c][2] * xyz[2];
        const double flat = m[c][0] * white[0] + m[c][1] * white[1] + m[c][2] * white[2];
        rgb[c] = value / flat;
    }
    return float3{float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

}  // namespace

// KHR_materials_iridescence's thin film (kernels/iridescence.h) against the exact reflectance of a water film
// (n = 1.33) on glass (n = 1.5, F0 0.04) at normal incidence: Airy's sum of every bounce inside the film, per
// wavelength, turned into RGB as above. glTF's model (Schlick terms, two orders, a Gaussian fit of the matching
// functions) stays within 0.0035 of it from 200 to 600 nm, where the colours swing from 0.006 to 0.04.
TEST(ThinFilm, MatchesTheExactInterferenceOfAWaterFilmOnGlass) {
    const double r12 = (1.0 - 1.33) / (1.0 + 1.33), r23 = (1.33 - 1.5) / (1.33 + 1.5);
    for (float thickness : {200.0f, 300.0f, 400.0f, 500.0f, 600.0f}) {
        const float3 exact = spectrum_rgb([&](double wavelength) {
            const std::complex<double> phase = std::polar(1.0, 4.0 * M_PI * 1.33 * thickness / wavelength);
            return std::norm((r12 + r23 * phase) / (1.0 + r12 * r23 * phase));
        });
        const float3 film = rt_thin_film_fresnel(1.33f, 1.0f, thickness, float3{0.04f, 0.04f, 0.04f});
        SCOPED_TRACE(thickness);
        expect_near3(film, exact, 0.0035f);
    }
    // Without a film: the base's reflectance (the model's two orders leave it 0.007 high).
    const float3 bare = rt_thin_film_fresnel(1.33f, 1.0f, 0.0f, float3{0.04f, 0.04f, 0.04f});
    expect_near3(bare, float3{0.04f, 0.04f, 0.04f}, 0.008f);
    // Toward grazing both interfaces' Schlick terms grow: the film reflects several times more.
    auto mean = [](float3 v) { return (v.x + v.y + v.z) / 3.0f; };
    const float3 head_on = rt_thin_film_fresnel(1.33f, 1.0f, 400.0f, float3{0.04f, 0.04f, 0.04f});
    const float3 grazing = rt_thin_film_fresnel(1.33f, 0.1f, 400.0f, float3{0.04f, 0.04f, 0.04f});
    EXPECT_GT(mean(grazing), 5.0f * mean(head_on));
    EXPECT_LE(std::max({grazing.x, grazing.y, grazing.z}), 1.0f);
    // A metal's colour as the base keeps its hue without a film.
    const float3 gold = rt_thin_film_fresnel(1.5f, 1.0f, 0.0f, float3{1.0f, 0.78f, 0.34f});
    EXPECT_GT(gold.x, gold.y);
    EXPECT_GT(gold.y, gold.z);
}

namespace {

// An opaque glTF material as device_material makes it: F0 0.04, metal-rough, no maps.
Material opaque_gltf(float metallic, float roughness, float clearcoat, float clearcoat_roughness) {
    Material m{};
    m.specular = float4{1, 1, 1, metallic * (1 - 0.5f * roughness)};
    m.fresnel = float4{0.04f, 0.96f, 5.0f, 0.0f};
    m.flags = RT_MATERIAL_METAL_ROUGH;
    m.metallic = metallic;
    m.roughness = roughness;
    m.metal_rough_map = m.emissive_map = m.occlusion_map = m.normal_map = RT_NONE;
    m.specular_map = m.specular_color_map = m.iridescence_map = m.iridescence_thickness_map = RT_NONE;
    m.clearcoat_map = m.clearcoat_roughness_map = RT_NONE;
    m.clearcoat = float4{clearcoat, clearcoat_roughness, 0, 0};
    return m;
}

}  // namespace

// KHR_materials_clearcoat: a varnish (F0 0.04) over a red metal reflects its share uncoloured and passes the rest:
// head-on r = c 0.04 gloss_c + (1 - c 0.04) r_base, and the tint moves toward white by the coat's share.
TEST(GltfMaterial, ClearcoatAddsAnUncolouredReflectionOverTheBase) {
    KernelGlobals kg{};  // no maps: nothing is fetched
    const float3 red{0.8f, 0.1f, 0.1f};
    const float4 uv{0, 0, 0, 0};
    SurfaceTerms bare = rt_surface_terms(kg, opaque_gltf(1.0f, 0.0f, 0.0f, 0.0f), red, uv, -1.0f);
    EXPECT_NEAR(bare.specular.w, 1.0f, 1e-6f);
    expect_near3(rt_xyz(bare.specular), red);
    SurfaceTerms coated = rt_surface_terms(kg, opaque_gltf(1.0f, 0.0f, 1.0f, 0.5f), red, uv, -1.0f);
    const float coat = 0.04f * 0.75f, base = 1.0f - 0.04f;  // coat: F0 x its gloss (1 - 0.5 / 2)
    EXPECT_NEAR(coated.specular.w, coat + base, 1e-6f);
    expect_near3(rt_xyz(coated.specular), (red * base + float3{coat, coat, coat}) / (coat + base), 1e-6f);
    // A matte dielectric under a coat: mostly diffuse head-on, a mirror of the sky toward grazing.
    SurfaceTerms matte_head_on = rt_surface_terms(kg, opaque_gltf(0.0f, 1.0f, 1.0f, 0.0f), red, uv, -1.0f);
    SurfaceTerms matte_grazing = rt_surface_terms(kg, opaque_gltf(0.0f, 1.0f, 1.0f, 0.0f), red, uv, -0.05f);
    EXPECT_LT(matte_head_on.specular.w, 0.1f);
    EXPECT_GT(matte_grazing.specular.w, 0.75f);
    EXPECT_GT(matte_grazing.specular.z, 0.9f) << "the coat's reflection is white";
}
