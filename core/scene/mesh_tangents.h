// Tangents for normal maps on meshes whose file has none (glTF says to generate them, MikkTSpace-style): per
// triangle, the direction in which u grows, accumulated at each corner weighted by the corner's angle, then made
// orthogonal to the vertex normal (Gram-Schmidt); the sign records whether v runs along cross(normal, tangent)
// or against it (mirrored UVs).
#pragma once

#include "core/scene/scene.h"

namespace prism {

// Fills mesh.tangents from its positions, normals (the geometric ones where the mesh has none) and `uv_set`
// (0: uv0, 1: uv1). Leaves them empty when the mesh has no such texture coordinates. A vertex no triangle gives
// a usable direction gets any unit vector orthogonal to its normal.
void generate_tangents(Mesh& mesh, uint32_t uv_set);

}  // namespace prism
