// Whether a mesh is the boundary of a solid, so that a point just behind its surface lies inside it. The shade
// stage then traces no shadow ray from such a point towards a light outside the mesh's bounds: every path from
// inside a closed surface to a point outside it crosses the surface, and shadow rays stop at every surface, so
// that ray would be blocked whatever else the scene holds (docs/kernels.md, "Shadow rays from inside a solid").
#pragma once

#include "core/scene/scene.h"

namespace prism {

// True when, with vertices at equal positions taken as one (glTF splits a vertex at every UV or normal seam):
// - every edge is shared by exactly two triangles, which run along it in opposite directions (closed, one
//   consistent winding), triangles whose corners fall on fewer than three positions left out;
// - every connected piece encloses a volume greater than 1e-4 of its bounding box's (its winding faces outward,
//   counter-clockwise seen from outside, and it is no flat double-sided sheet whose two sides rounding could swap);
// - every position is finite and every index is in range.
// Otherwise false (open, non-manifold or inside-out meshes): nothing is assumed of them.
bool is_closed_solid(const Mesh& mesh);

}  // namespace prism
