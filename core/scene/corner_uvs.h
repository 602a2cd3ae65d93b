// Texture coordinates given per triangle corner (MeshLab's "wedge" coordinates in PLY faces) where the mesh keeps
// one attribute set per vertex: a vertex whose corners disagree (a texture seam) is split into one vertex per
// distinct coordinate, carrying its position, normal and colour along.
#pragma once

#include <span>

#include <glm/vec2.hpp>

#include "core/scene/scene.h"

namespace prism {

// corner_uvs[3 t + k]: triangle t's corner k. Replaces mesh.uv0; triangles are renumbered, their order kept.
// Normals should be computed before (a split vertex keeps the smooth normal of the welded mesh).
void apply_corner_uvs(Mesh& mesh, std::span<const glm::vec2> corner_uvs);

}  // namespace prism
