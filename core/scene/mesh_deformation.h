// Meshes whose vertices move: morph targets (glTF 2.0, "Morph Targets": each target's displacements scaled by its
// weight and added to the rest attributes) and skins (glTF 2.0, "Skins": linear blend skinning, each vertex moved by
// the weighted sum of its joints' matrices, a joint's world transform times its inverse bind matrix). The loaders
// pose a mesh once with these functions when nothing animates it; a NodeAnimation keeps a MeshDeformation for a mesh
// whose weights are keyed or whose joints move, and poses it again for every frame of a sequence or the viewer.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace prism {

// One morph target's displacements, one per vertex (an attribute the target does not move is empty).
struct MorphTarget {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec3> tangents;
};

// Which joints move each vertex, and how much: `per_vertex` influences a vertex, with weights as the file gives them
// (finite, not negative); a vertex's blend is divided by the sum of its weights (all 0: the vertex stays).
struct SkinInfluences {
    uint32_t per_vertex = 0;
    std::vector<uint32_t> joints;  // per vertex x per_vertex: an index into the skin's joint matrices
    std::vector<float> weights;
};

// The attributes a deformation moves.
struct DeformedVertices {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;   // empty: the mesh has none
    std::vector<glm::vec4> tangents;  // empty: the mesh has none
};

// `vertices` plus each target's displacements times its weight (weights past the targets are ignored, missing
// ones are 0); moved normals and tangents are normalized again.
void morph_vertices(DeformedVertices& vertices, std::span<const MorphTarget> targets, std::span<const float> weights);

// One target's share of morph_vertices, for a caller that reads targets one at a time: the displacements times
// `weight` added, nothing normalized. Returns which of normals (bit 0) and tangents (bit 1) it moved.
unsigned add_morph_target(DeformedVertices& vertices, const MorphTarget& target, float weight);
// morph_vertices' last step: the normals (`moved` bit 0) and tangents (bit 1) normalized again.
void normalize_morphed(DeformedVertices& vertices, unsigned moved);

// Each vertex moved by its influences' blend of `joint_matrices`; normals by the blend's inverse transpose (a
// skin may scale unevenly; a singular blend moves them by its linear part), tangents by its linear part.
void skin_vertices(DeformedVertices& vertices, const SkinInfluences& influences,
                   std::span<const glm::mat4> joint_matrices);

// A scene mesh posed anew at every moment of an animation (core/scene/node_animation.h).
struct MeshDeformation {
    uint32_t mesh = 0;      // the Scene::meshes entry it poses: its positions, normals and tangents
    DeformedVertices rest;  // the attributes before any target or skin
    std::vector<MorphTarget> targets;
    std::vector<float> weights;           // the targets' weights when no channel keys them
    int32_t weight_channel = -1;          // else the NodeAnimation::weight_channels entry that does
    std::vector<uint32_t> joints;         // a skin's joints: NodeAnimation::nodes entries (none: no skin)
    std::vector<glm::mat4> inverse_bind;  // one per joint
    SkinInfluences influences;
    // The joints' world transforms are taken relative to this node's (a scene file's placement of the model, which
    // its instance already carries); -1: as they are.
    int32_t space_node = -1;
};

}  // namespace prism
