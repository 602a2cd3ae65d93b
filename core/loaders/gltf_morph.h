// glTF morph targets, applied once when a file loads with the weights the file gives them (the node's "weights",
// else the mesh's defaults; animations do not key weights): each target's POSITION, NORMAL and TANGENT displacements,
// scaled by its weight, added to the primitive's attributes (glTF 2.0, "Morph Targets"), before any skin.
#pragma once

#include <span>
#include <string>

#include "core/scene/scene.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace prism::gltf {

// Whether any weight is non-zero for a target the primitive has (all zero: the mesh as stored).
bool morph_changes(const tinygltf::Primitive& primitive, std::span<const double> weights);

// Adds the weighted displacements to `mesh` (read from `primitive`: positions, and normals and tangents where both
// the mesh and the target have them; normals and tangents are normalized again). Weights beyond the primitive's
// targets are ignored, missing ones are 0. Throws prism::Error "<file>: <what>: ..." for a weight that is not a
// finite float or a target whose attribute is not VEC3 or not as long as POSITION.
void apply_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                         std::span<const double> weights, Mesh& mesh, const std::string& what, const std::string& file);

}  // namespace prism::gltf
