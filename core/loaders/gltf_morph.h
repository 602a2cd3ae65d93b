// glTF morph targets (glTF 2.0, "Morph Targets"): each target's POSITION, NORMAL and TANGENT displacements read into
// MorphTarget (core/scene/mesh_deformation.h), and a primitive's attributes moved by them with the weights the file
// gives (the node's "weights", else the mesh's defaults), before any skin. An animation that keys the weights keeps
// the targets and poses the mesh again at every moment.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/scene/mesh_deformation.h"
#include "core/scene/scene.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace prism::gltf {

// Whether any weight is non-zero for a target the primitive has (all zero: the mesh as stored).
bool morph_changes(const tinygltf::Primitive& primitive, std::span<const double> weights);

// The weights as floats, one per target of the primitive (missing ones 0). Throws prism::Error "<file>: <what>: ..."
// for a weight that is not a finite float.
std::vector<float> morph_weights(const tinygltf::Primitive& primitive, std::span<const double> weights,
                                 const std::string& what, const std::string& file);

// Target t of the primitive as displacements for `mesh` (positions, and normals and tangents where both the mesh and
// the target have them). Throws prism::Error "<file>: <what>: ..." for a target attribute that is not VEC3 or not as
// long as POSITION.
MorphTarget read_morph_target(const tinygltf::Model& model, const tinygltf::Primitive& primitive, size_t t,
                              const Mesh& mesh, const std::string& what, const std::string& file);
// Every target of the primitive (a mesh an animation morphs keeps them all).
std::vector<MorphTarget> read_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                            const Mesh& mesh, const std::string& what, const std::string& file);

// Adds the weighted displacements to `mesh`, as morph_vertices does, reading one target at a time: targets that
// share one accessor are never all in memory at once. Weights beyond the primitive's targets are ignored, missing
// ones are 0.
void apply_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                         std::span<const double> weights, Mesh& mesh, const std::string& what, const std::string& file);

// The attributes a deformation moves, moved out of `mesh` and back.
DeformedVertices take_deformed(Mesh& mesh);
void put_deformed(Mesh& mesh, DeformedVertices&& vertices);

}  // namespace prism::gltf
