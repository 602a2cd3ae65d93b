// glTF skins, applied once when a file loads: the joints stand where the file's nodes put them (an animation does
// not move them), and each vertex moves by linear blend skinning (glTF 2.0, "Skins"): the weighted sum of its joints'
// matrices, each the joint's world transform times its inverse bind matrix. The skinned mesh node's own transform
// is ignored, as the spec says; the result is in world space.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/loaders/gltf_accessor.h"
#include "core/scene/scene.h"

namespace prism::gltf {

struct Skin {
    std::vector<int> joints;         // node indices
    int inverse_bind_matrices = -1;  // a MAT4 accessor; -1: identity matrices (the spec's default)
};

// The document's "skins" array (taken out of the JSON before tinygltf parses it: gltf_rest_pose.h). Throws
// prism::Error naming `file` for an entry that is not a skin.
std::vector<Skin> parse_skins(const nlohmann::json& skins, const std::string& file);

// Each joint's world transform times its inverse bind matrix. `node_world[n]` is node n's world transform. Throws
// prism::Error naming `file` when a joint is not a node or the inverse bind matrices are too few.
std::vector<glm::mat4> joint_matrices(const tinygltf::Model& model, const Skin& skin,
                                      std::span<const glm::mat4> node_world, const std::string& file);

// One set of a vertex's influences: JOINTS_n and WEIGHTS_n, four per vertex.
struct Influences {
    FloatArray joints;
    FloatArray weights;
};

// Moves the mesh's positions, normals and tangents by their vertices' influences (weights normalized to sum 1; a
// vertex with no weight stays where it is). Throws prism::Error "<file>: <what>: ..." for a joint the skin does not
// have or a weight that is negative or not finite.
void apply_skin(Mesh& mesh, std::span<const glm::mat4> joints, std::span<const Influences> influences,
                const std::string& what, const std::string& file);

}  // namespace prism::gltf
