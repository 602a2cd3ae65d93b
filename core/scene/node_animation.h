// A glTF animation's node transforms, kept so a sequence or the viewer can play them: the nodes above every moving
// instance, the channels that key their translation, rotation and scale, and which instance hangs from which node.
// Sampling follows the glTF 2.0 spec (Appendix C): STEP, LINEAR (rotations by spherical interpolation) and
// CUBICSPLINE (Hermite, tangents scaled by the key interval), clamped to the first and last key.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/scene/mesh_deformation.h"

namespace prism {

// A node as the file places it when nothing animates it: its local matrix, or its TRS when a channel may key it.
struct AnimationNode {
    int32_t parent = -1;  // index into NodeAnimation::nodes, always below this node's own
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    glm::mat4 matrix{1.0f};  // the local transform as loaded (used as it is unless a channel keys this node)
    bool keyed = false;      // some channel keys this node: its local transform is built from TRS
};

enum class AnimationPath : uint8_t { Translation, Rotation, Scale };
enum class AnimationInterpolation : uint8_t { Step, Linear, CubicSpline };

struct AnimationChannel {
    uint32_t node = 0;  // index into NodeAnimation::nodes
    AnimationPath path = AnimationPath::Translation;
    AnimationInterpolation interpolation = AnimationInterpolation::Linear;
    std::vector<float> times;       // seconds, increasing
    std::vector<glm::vec4> values;  // xyz (w for rotations); CUBICSPLINE: in-tangent, value, out-tangent per key
    double clip_seconds = 0.0;      // the length of the animation (clip) it belongs to, which loops on its own
};

// A channel that keys a node's morph target weights: `width` weights per key (CUBICSPLINE: in-tangents, values and
// out-tangents, 3 x width per key).
struct WeightChannel {
    AnimationInterpolation interpolation = AnimationInterpolation::Linear;
    uint32_t width = 0;
    std::vector<float> times;  // seconds, increasing
    std::vector<float> values;
    double clip_seconds = 0.0;
};

// An instance of Scene::instances that hangs from an animated node: its transform is the node's world transform
// times `local` (EXT_mesh_gpu_instancing's per-instance transform, else identity).
struct AnimatedInstance {
    uint32_t instance = 0;
    uint32_t node = 0;  // index into NodeAnimation::nodes
    glm::mat4 local{1.0f};
};

// A light of Scene::lights that hangs from an animated node: at the node's origin, shining down its -z (as the
// loader placed it).
struct AnimatedLight {
    uint32_t light = 0;
    uint32_t node = 0;  // index into NodeAnimation::nodes
};

struct NodeAnimation {
    std::string name;       // for messages and `prism info`
    double duration = 0.0;  // seconds: the longest clip played (each clip loops over its own length)
    std::vector<AnimationNode> nodes;
    std::vector<AnimationChannel> channels;
    std::vector<AnimatedInstance> instances;
    int32_t camera_node = -1;  // the node the scene's camera hangs from, when a keyed node is above it
    std::vector<WeightChannel> weight_channels;
    std::vector<MeshDeformation> deformations;  // meshes posed anew at every moment: skinned, or weights keyed
    std::vector<AnimatedLight> lights;

    bool plays() const {
        return (!channels.empty() || !weight_channels.empty()) &&
               (!instances.empty() || camera_node >= 0 || !deformations.empty() || !lights.empty());
    }
};

// Adds `part`'s nodes, channels, instances, deformations and lights to `into`: `part`'s roots hang from a new node
// placed by `placement`, its instances are numbered from `first_instance` and its lights from `first_light` (a scene
// file placing an animated model, whose meshes are already the scene's; the model's camera is not carried over).
// Both animations play together, over the longer duration. A mesh `into` already deforms (the same model placed
// again shares its meshes) is not added twice.
void append_node_animation(NodeAnimation& into, const NodeAnimation& part, uint32_t first_instance,
                           uint32_t first_light, const glm::mat4& placement);

// A channel's value at `seconds` (xyz, or a normalized quaternion as xyzw for rotations).
glm::vec4 sample_channel(const AnimationChannel& channel, float seconds);

// A weight channel's `width` weights at `seconds`.
std::vector<float> sample_weights(const WeightChannel& channel, float seconds);

// Every node's world transform at `seconds` into the animation (each channel looped over its clip's length).
std::vector<glm::mat4> node_world_transforms(const NodeAnimation& animation, double seconds);

// The animated instances' transforms at `seconds`, written into `transforms` (one per scene instance). An instance
// whose transform would not be finite keeps the one `transforms` holds.
void apply_node_animation(const NodeAnimation& animation, double seconds, std::vector<glm::mat4>& transforms);

// Each deformed mesh's attributes at `seconds`, one entry per NodeAnimation::deformations entry. An entry whose
// pose is not finite everywhere (keys that compose to infinity) comes back empty: its mesh keeps the pose it has.
std::vector<DeformedVertices> deformed_meshes_at(const NodeAnimation& animation, double seconds);

}  // namespace prism
