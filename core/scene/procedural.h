// Geometry and textures generated in code, so the built-in scenes and tests need no files.
#pragma once

#include <array>

#include "core/scene/scene.h"

namespace prism {

// A unit-radius UV sphere around the origin: `rings` bands from pole to pole, `segments` around; the poles are
// single vertices' fans, so it has segments * (2 * rings - 2) triangles, counter-clockwise seen from outside.
// Normals point outward, uv0 = (segment / segments, ring / rings), colours are a smooth gradient over the surface.
Mesh make_uv_sphere(int rings, int segments);

// A square in the y = 0 plane, centred on the origin, side `size`, facing +Y (two triangles), uv0 over [0, 1].
Mesh make_ground_plane(float size);

// A `size` x `size` RGBA8 checkerboard of `squares` x `squares` cells in two colours (linear RGB in [0, 1]).
Texture make_checker_texture(int size, int squares, glm::vec3 light, glm::vec3 dark);

// Six `size` x `size` faces (scene.h order +X, -X, +Y, -Y, +Z, -Z; OpenGL cube-map texel orientation) of a sky:
// a zenith-to-horizon gradient, a bright horizon band and a darker ground below it.
std::array<Texture, 6> make_sky_cube_map(int size);

// Packs linear RGB(A) in [0, 1] into Prism's sRGB RGBA8 texel (r in the low byte).
uint32_t pack_srgb8(glm::vec4 linear);

}  // namespace prism
