// glTF animations (glTF 2.0, "Animations"): the file's animations chosen to play, their channels that key a node's
// translation, rotation or scale read into samplers Prism can play (core/scene/node_animation.h). The "animations"
// array is taken out of the JSON before tinygltf parses it (gltf_rest_pose.h), so it is read here from the JSON,
// its keys through the accessors tinygltf did read.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

#include "core/scene/node_animation.h"

namespace tinygltf {
class Model;
class Node;
}  // namespace tinygltf

namespace prism::gltf {

// A channel as the file gives it: `node` is the file's node index.
struct FileChannel {
    int node = -1;
    bool weights = false;          // it keys the node's morph target weights (weight_channel), not its transform
    AnimationChannel channel;      // its `node` field is set once the node has a place in NodeAnimation::nodes
    WeightChannel weight_channel;  // (weights)

    float last_key() const { return weights ? weight_channel.times.back() : channel.times.back(); }
};

struct FileAnimation {
    std::string name;            // the file's name for the one played, "animation N", or "all N animations"
    size_t animation_count = 0;  // how many the file has
    std::vector<FileChannel> channels;
    size_t unplayable = 0;              // channels left out: KHR_animation_pointer targets
    size_t malformed = 0;               // channels left out because they are malformed (or too large)
    size_t key_floats_left = 0;         // what more channels may copy (read_animations sets the budget)
    std::vector<std::string> warnings;  // "<file>: ..." for the first few of those, then their count
};

// The animations of the document's "animations" array (null: the file has none) that `selection` names: empty, the
// first; "all", every one, played together; a number, that one; else the one of that name. A selection the file does
// not have throws prism::Error naming `file` and listing its animations. A malformed channel is left out with a
// warning naming `file` and the cause, so the scene still draws as its nodes place it.
FileAnimation read_animations(const nlohmann::json& animations, const tinygltf::Model& model, const std::string& file,
                              const std::string& selection);

// Builds the scene's NodeAnimation while the importer walks the node trees: every node it enters gets a place
// (parents before children), every instance below a keyed node is recorded with the node it hangs from, and so are
// the scene's camera, its lights and the meshes whose skins or weights the animation moves.
class AnimationRig {
public:
    AnimationRig(FileAnimation animation, const tinygltf::Model& model, std::string file);

    // Where a node sits in NodeAnimation::nodes and whether a keyed node is on its path (itself included).
    struct Place {
        int32_t slot = -1;
        bool moves = false;
    };
    // The node the importer enters below `parent` (a root's parent is Place{}), with its local transform.
    Place enter(int node_index, const glm::mat4& local, Place parent);
    // An instance the importer added for a node at `place`: its transform is the node's world times `local`.
    void add_instance(uint32_t instance, Place place, const glm::mat4& local);
    // The scene's camera hangs from the node at `place`.
    void set_camera(Place place);
    // Scene light `light` hangs from the node at `place`.
    void add_light(uint32_t light, Place place);

    // Whether a channel keys the morph target weights of (entered) node `node_index`.
    bool weights_keyed(int node_index) const;
    // Whether a keyed node is on the path of (entered) node `node_index`: the node moves.
    bool moves(int node_index) const;
    // A mesh posed anew at every moment: its weights keyed on node `weights_node` (-1: its own weights), its skin's
    // `joints` (the file's node indices, all entered; empty: no skin).
    void add_deformation(MeshDeformation deformation, int weights_node, const std::vector<int>& joints);

    // The animation to play (channels that move no recorded instance left out), and the warnings: what is not
    // played, and the malformed channels read_first_animation left out.
    NodeAnimation finish(std::vector<std::string>& warnings);

private:
    FileAnimation file_animation_;
    const tinygltf::Model& model_;
    std::string file_;
    std::vector<bool> keyed_;                   // per file node: a playable channel keys its transform
    std::vector<int32_t> weights_channel_;      // per file node: the last channel of file_animation_ keying its weights
    std::vector<int32_t> slot_of_;              // per file node: its place, -1 before it is entered
    std::vector<bool> slot_moves_;              // per place: a keyed node is on its path
    std::vector<int32_t> deformation_weights_;  // per deformation: the weights channel of file_animation_, or -1
    NodeAnimation animation_;
};

}  // namespace prism::gltf
