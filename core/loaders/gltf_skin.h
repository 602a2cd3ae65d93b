// glTF skins (glTF 2.0, "Skins"): the joints and inverse bind matrices of the document's skins, each vertex's
// influences (JOINTS_n, WEIGHTS_n) checked and read into SkinInfluences, and linear blend skinning
// (core/scene/mesh_deformation.h) with the joints where the file's nodes put them. The skinned mesh node's own
// transform is ignored, as the spec says; the result is in world space. An animation that moves the joints keeps
// the influences and poses the mesh again at every moment.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/loaders/gltf_accessor.h"
#include "core/scene/mesh_deformation.h"

namespace prism::gltf {

struct Skin {
    std::vector<int> joints;         // node indices
    int inverse_bind_matrices = -1;  // a MAT4 accessor; -1: identity matrices (the spec's default)
};

// The document's "skins" array (taken out of the JSON before tinygltf parses it: gltf_rest_pose.h). Throws
// prism::Error naming `file` for an entry that is not a skin.
std::vector<Skin> parse_skins(const nlohmann::json& skins, const std::string& file);

// The skin's inverse bind matrices, one per joint (identity matrices when it has none, the spec's default). Throws
// prism::Error naming `file` when they are too few.
std::vector<glm::mat4> inverse_bind_matrices(const tinygltf::Model& model, const Skin& skin, const std::string& file);

// Each joint's world transform times its inverse bind matrix. `node_world[n]` is node n's world transform. Throws
// prism::Error naming `file` when a joint is not a node or the inverse bind matrices are too few.
std::vector<glm::mat4> joint_matrices(const tinygltf::Model& model, const Skin& skin,
                                      std::span<const glm::mat4> node_world, const std::string& file);

// One set of a vertex's influences: JOINTS_n and WEIGHTS_n, four per vertex.
struct Influences {
    FloatArray joints;
    FloatArray weights;
};

// The sets' influences on `vertex_count` vertices of a skin with `joint_count` joints. Throws prism::Error
// "<file>: <what>: ..." for a joint the skin does not have (with a weight above 0) or a weight that is negative or
// not finite.
SkinInfluences skin_influences(std::span<const Influences> sets, size_t vertex_count, size_t joint_count,
                               const std::string& what, const std::string& file);

}  // namespace prism::gltf
