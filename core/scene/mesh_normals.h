// Smooth vertex normals for meshes that come without them (laser scans such as the Stanford models): area-weighted
// averages of the faces around each vertex. Without them a mirror-like scan reflects as facets.
#pragma once

#include "core/scene/scene.h"

namespace prism {

// Fills mesh.normals (replacing any) from the triangles; vertices on no usable triangle get (0, 0, 1).
void compute_smooth_normals(Mesh& mesh);

}  // namespace prism
