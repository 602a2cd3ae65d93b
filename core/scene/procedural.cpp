#include "core/scene/procedural.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace prism {
namespace {

float linear_to_srgb(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

uint32_t to_byte(float value) { return static_cast<uint32_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }

// OpenGL cube-map convention: (sc, tc) in [-1, 1] on face `face` -> direction; row 0 of a side face is its top.
glm::vec3 cube_direction(int face, float sc, float tc) {
    switch (face) {
        case 0: return {1.0f, -tc, -sc};
        case 1: return {-1.0f, -tc, sc};
        case 2: return {sc, 1.0f, tc};
        case 3: return {sc, -1.0f, -tc};
        case 4: return {sc, -tc, 1.0f};
        default: return {-sc, -tc, -1.0f};
    }
}

glm::vec3 sky_color(glm::vec3 direction) {
    float height = glm::normalize(direction).y;
    const glm::vec3 zenith{0.18f, 0.36f, 0.80f}, horizon{0.85f, 0.90f, 0.98f}, ground{0.22f, 0.20f, 0.17f};
    if (height >= 0.0f) {
        glm::vec3 sky = glm::mix(horizon, zenith, std::pow(height, 0.5f));
        return sky + glm::vec3(0.15f) * std::exp(-height * 40.0f);  // a soft bright band just above the horizon
    }
    return glm::mix(horizon * 0.6f, ground, std::min(1.0f, -height * 6.0f));
}

}  // namespace

uint32_t pack_srgb8(glm::vec4 linear) {
    return to_byte(linear_to_srgb(linear.x)) | to_byte(linear_to_srgb(linear.y)) << 8 |
           to_byte(linear_to_srgb(linear.z)) << 16 | to_byte(linear.w) << 24;
}

Mesh make_uv_sphere(int rings, int segments) {
    Mesh mesh;
    mesh.name = "uv sphere";
    for (int ring = 0; ring <= rings; ++ring) {
        float theta = glm::pi<float>() * ring / rings;
        // The poles and the seam get exactly the positions they share (sin(pi) and sin(2 pi) are not 0 in float):
        // the sphere is closed, with no crack at the seam or the south pole (core/scene/closed_solid.h).
        float sin_theta = ring == 0 || ring == rings ? 0.0f : std::sin(theta);
        float cos_theta = ring == 0 ? 1.0f : ring == rings ? -1.0f : std::cos(theta);
        for (int segment = 0; segment <= segments; ++segment) {
            float phi = segment == segments ? 0.0f : glm::two_pi<float>() * segment / segments;
            glm::vec3 p{sin_theta * std::cos(phi), cos_theta, sin_theta * std::sin(phi)};
            mesh.positions.push_back(p);
            mesh.normals.push_back(p);
            mesh.uv0.push_back({static_cast<float>(segment) / segments, static_cast<float>(ring) / rings});
            // Smooth over the sphere and continuous across the seam (a function of the position only).
            mesh.colors.push_back({0.55f + 0.45f * p.x, 0.55f + 0.45f * p.y, 0.55f + 0.45f * p.z, 1.0f});
        }
    }
    auto vertex = [&](int ring, int segment) { return static_cast<uint32_t>(ring * (segments + 1) + segment); };
    for (int ring = 0; ring < rings; ++ring) {
        for (int segment = 0; segment < segments; ++segment) {
            uint32_t v00 = vertex(ring, segment), v01 = vertex(ring, segment + 1);
            uint32_t v10 = vertex(ring + 1, segment), v11 = vertex(ring + 1, segment + 1);
            // At the poles one triangle of each quad has zero area (its two pole corners coincide): leave it out.
            if (ring != 0) mesh.triangles.push_back({v00, v01, v10});
            if (ring != rings - 1) mesh.triangles.push_back({v01, v11, v10});
        }
    }
    mesh.triangle_materials.assign(mesh.triangles.size(), 0);
    return mesh;
}

Mesh make_ground_plane(float size) {
    Mesh mesh;
    mesh.name = "ground plane";
    float h = size * 0.5f;
    mesh.positions = {{-h, 0.0f, -h}, {h, 0.0f, -h}, {h, 0.0f, h}, {-h, 0.0f, h}};
    mesh.normals.assign(4, {0.0f, 1.0f, 0.0f});
    mesh.uv0 = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    mesh.triangles = {{0, 2, 1}, {0, 3, 2}};  // counter-clockwise seen from above
    mesh.triangle_materials.assign(2, 0);
    return mesh;
}

Texture make_checker_texture(int size, int squares, glm::vec3 light, glm::vec3 dark) {
    Texture texture;
    texture.name = "procedural checkerboard";
    texture.width = texture.height = size;
    texture.encoding = TextureEncoding::Srgb8;
    texture.texels.resize(static_cast<size_t>(size) * size);
    uint32_t light_texel = pack_srgb8(glm::vec4(light, 1.0f)), dark_texel = pack_srgb8(glm::vec4(dark, 1.0f));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            texture.texels[static_cast<size_t>(y) * size + x] =
                ((x * squares / size + y * squares / size) % 2 == 0) ? light_texel : dark_texel;
    return texture;
}

std::array<Texture, 6> make_sky_cube_map(int size) {
    static const char* names[6] = {"sky +X", "sky -X", "sky +Y", "sky -Y", "sky +Z", "sky -Z"};
    std::array<Texture, 6> faces;
    for (int face = 0; face < 6; ++face) {
        Texture& texture = faces[face];
        texture.name = std::string("procedural ") + names[face];
        texture.width = texture.height = size;
        texture.encoding = TextureEncoding::Srgb8;
        texture.texels.resize(static_cast<size_t>(size) * size);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                float sc = 2.0f * (x + 0.5f) / size - 1.0f, tc = 2.0f * (y + 0.5f) / size - 1.0f;
                texture.texels[static_cast<size_t>(y) * size + x] =
                    pack_srgb8(glm::vec4(sky_color(cube_direction(face, sc, tc)), 1.0f));
            }
    }
    return faces;
}

}  // namespace prism
