#include "core/loaders/gltf_animation.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/loaders/gltf_accessor.h"
#include "core/util/error.h"

namespace prism::gltf {
namespace {

constexpr size_t kMalformedChannelsNamed = 8;       // warnings that name a malformed channel; the rest are counted
constexpr size_t kMinKeyFloats = size_t(16) << 20;  // key floats all channels may copy, whatever the file's size

// The string at `key`, or `fallback` when there is none or it is not a string.
std::string string_of(const nlohmann::json& object, const char* key, const std::string& fallback = {}) {
    auto found = object.find(key);
    return found != object.end() && found->is_string() ? found->get<std::string>() : fallback;
}

// A non-negative index that fits an int, else -1.
int index_of(const nlohmann::json& object, const char* key) {
    auto found = object.find(key);
    if (found == object.end() || !found->is_number_integer()) return -1;
    const int64_t value = found->get<int64_t>();
    return value >= 0 && value <= INT32_MAX ? static_cast<int>(value) : -1;
}

// The floats an accessor holds as its header declares them (0 for one that does not exist: reading it fails).
size_t declared_floats(const tinygltf::Model& model, int accessor) {
    if (accessor < 0 || size_t(accessor) >= model.accessors.size()) return 0;
    const tinygltf::Accessor& a = model.accessors[size_t(accessor)];
    const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    return a.count * size_t(std::max(components, 1));
}

// A sampler's interpolation, key times and output values, or the reason it cannot be played. `floats_left`: what
// the file's keys may still take (FileAnimation::key_floats_left), charged before anything is read.
struct SamplerKeys {
    AnimationInterpolation interpolation = AnimationInterpolation::Linear;
    std::vector<float> times;
    FloatArray values;
};

std::string read_sampler(const tinygltf::Model& model, const nlohmann::json& sampler, SamplerKeys& keys,
                         const std::string& file, size_t& floats_left) {
    if (!sampler.is_object()) return "its sampler is not an object";
    const int input = index_of(sampler, "input"), output = index_of(sampler, "output");
    if (input < 0 || output < 0) return "its sampler has no input or output accessor";
    const std::string interpolation = string_of(sampler, "interpolation", "LINEAR");
    if (interpolation == "STEP")
        keys.interpolation = AnimationInterpolation::Step;
    else if (interpolation == "LINEAR")
        keys.interpolation = AnimationInterpolation::Linear;
    else if (interpolation == "CUBICSPLINE")
        keys.interpolation = AnimationInterpolation::CubicSpline;
    else
        return "interpolation '" + interpolation + "' is not STEP, LINEAR or CUBICSPLINE";
    // Channels may share accessors (and accessors bytes), so a small file could make every channel copy one large
    // accessor: the copies together may not exceed what the file's buffers hold (kMinKeyFloats at least).
    const size_t needed = declared_floats(model, input) + declared_floats(model, output);
    if (needed > floats_left)
        return "its keys (" + std::to_string(needed) +
               " floats) would pass what the file's channels may copy in all (its buffers' size in bytes, at least " +
               std::to_string(kMinKeyFloats) + ")";
    floats_left -= needed;
    const FloatArray times = read_floats(model, input, file);
    keys.values = read_floats(model, output, file);
    if (times.components != 1 || times.count == 0) return "its input is not a non-empty SCALAR accessor";
    for (size_t k = 0; k < times.count; ++k) {
        const float t = times.at(k, 0);
        if (!std::isfinite(t)) return "a key time is not finite";
        if (k > 0 && !(t >= times.at(k - 1, 0))) return "its key times decrease";
        keys.times.push_back(t);
    }
    for (float v : keys.values.values)
        if (!std::isfinite(v)) return "a key value is not finite";
    return {};
}

// The channel's keys, or the reason it cannot be played (read_sampler's, or an output of the wrong shape).
std::string read_keys(const tinygltf::Model& model, const nlohmann::json& sampler, AnimationChannel& channel,
                      const std::string& file, size_t& floats_left) {
    SamplerKeys keys;
    if (std::string cause = read_sampler(model, sampler, keys, file, floats_left); !cause.empty()) return cause;
    channel.interpolation = keys.interpolation;
    const FloatArray& values = keys.values;
    const int components = channel.path == AnimationPath::Rotation ? 4 : 3;
    const size_t per_key = channel.interpolation == AnimationInterpolation::CubicSpline ? 3 : 1;
    if (values.components != components)
        return "its output has " + std::to_string(values.components) + " components; " + std::to_string(components) +
               " expected";
    if (values.count != keys.times.size() * per_key)
        return "its output has " + std::to_string(values.count) + " values for " + std::to_string(keys.times.size()) +
               " keys";
    channel.times = std::move(keys.times);
    channel.values.reserve(values.count);
    for (size_t k = 0; k < values.count; ++k)
        channel.values.emplace_back(values.at(k, 0), values.at(k, 1), values.at(k, 2),
                                    components == 4 ? values.at(k, 3) : 0.0f);
    return {};
}

// A weights channel's keys: `channel.width` (the node's morph targets) weights per key.
std::string read_weight_keys(const tinygltf::Model& model, const nlohmann::json& sampler, WeightChannel& channel,
                             const std::string& file, size_t& floats_left) {
    SamplerKeys keys;
    if (std::string cause = read_sampler(model, sampler, keys, file, floats_left); !cause.empty()) return cause;
    channel.interpolation = keys.interpolation;
    const size_t per_key = (channel.interpolation == AnimationInterpolation::CubicSpline ? 3 : 1) * channel.width;
    if (keys.values.components != 1) return "its output is not a SCALAR accessor of weights";
    if (keys.values.count != keys.times.size() * per_key)
        return "its output has " + std::to_string(keys.values.count) + " weights for " +
               std::to_string(keys.times.size()) + " keys of " + std::to_string(channel.width) + " morph targets";
    channel.times = std::move(keys.times);
    channel.values = std::move(keys.values.values);
    return {};
}

// How many morph targets the mesh of node `node` has (0: no mesh, or none): the width of its weights.
size_t morph_target_count(const tinygltf::Model& model, int node) {
    const int mesh = model.nodes[size_t(node)].mesh;
    if (mesh < 0 || size_t(mesh) >= model.meshes.size()) return 0;
    size_t targets = 0;
    for (const tinygltf::Primitive& primitive : model.meshes[size_t(mesh)].primitives)
        targets = std::max(targets, primitive.targets.size());
    return targets;
}

// One clip's channels appended to `out`; `out.malformed` counts the channels left out over every clip read.
void read_clip(const nlohmann::json& animation, const std::string& name, const tinygltf::Model& model,
               const std::string& file, FileAnimation& out) {
    auto channels = animation.find("channels");
    auto samplers = animation.find("samplers");
    if (channels == animation.end() || !channels->is_array()) return;
    const size_t first = out.channels.size();
    // A file of a million malformed channels gets a few lines, then a count.
    auto left_out = [&](const std::string& warning) {
        if (++out.malformed <= kMalformedChannelsNamed) out.warnings.push_back(Error(warning).what());
    };
    for (size_t c = 0; c < channels->size(); ++c) {
        const nlohmann::json& entry = (*channels)[c];
        const std::string what = "animation '" + name + "', channel " + std::to_string(c);
        auto target = entry.is_object() ? entry.find("target") : entry.end();
        if (!entry.is_object() || target == entry.end() || !target->is_object()) {
            left_out(file + ": " + what + " has no target; left out");
            continue;
        }
        const std::string path = string_of(*target, "path");
        const int node = index_of(*target, "node");
        FileChannel channel;
        channel.node = node;
        channel.weights = path == "weights";
        if (path == "translation")
            channel.channel.path = AnimationPath::Translation;
        else if (path == "rotation")
            channel.channel.path = AnimationPath::Rotation;
        else if (path == "scale")
            channel.channel.path = AnimationPath::Scale;
        if ((path != "translation" && path != "rotation" && path != "scale" && path != "weights") || node < 0) {
            ++out.unplayable;  // KHR_animation_pointer's targets
            continue;
        }
        std::string cause;
        if (node >= static_cast<int>(model.nodes.size())) cause = "node " + std::to_string(node) + " does not exist";
        if (cause.empty() && channel.weights) {
            channel.weight_channel.width = uint32_t(std::min<size_t>(morph_target_count(model, node), UINT32_MAX));
            if (channel.weight_channel.width == 0)
                cause = "it keys the weights of node " + std::to_string(node) + ", whose mesh has no morph targets";
        }
        const int sampler = index_of(entry, "sampler");
        if (cause.empty() && (samplers == animation.end() || !samplers->is_array() || sampler < 0 ||
                              size_t(sampler) >= samplers->size()))
            cause = "its sampler does not exist";
        if (cause.empty()) {
            try {
                const nlohmann::json& keys = (*samplers)[size_t(sampler)];
                cause = channel.weights
                            ? read_weight_keys(model, keys, channel.weight_channel, file, out.key_floats_left)
                            : read_keys(model, keys, channel.channel, file, out.key_floats_left);
            } catch (const Error& error) {  // an accessor's bytes: "<file>: accessor N: ..."
                left_out(std::string(error.what()) + " (" + what + "; left out)");
                continue;
            }
        }
        if (!cause.empty()) {
            left_out(file + ": " + what + ": " + cause + "; left out");
            continue;
        }
        out.channels.push_back(std::move(channel));
    }
    // The clip loops over its last key (glTF leaves looping to the viewer; its sample viewer loops each clip).
    double seconds = 0.0;
    for (size_t c = first; c < out.channels.size(); ++c)
        seconds = std::max(seconds, double(out.channels[c].last_key()));
    for (size_t c = first; c < out.channels.size(); ++c)
        out.channels[c].channel.clip_seconds = out.channels[c].weight_channel.clip_seconds = seconds;
}

// The file's name for clip `i`, quoted short in warnings and `prism info`, else "animation i".
std::string clip_name(const nlohmann::json& animations, size_t i) {
    const std::string name = animations[i].is_object() ? shorten(string_of(animations[i], "name"), 64) : "";
    return name.empty() ? "animation " + std::to_string(i) : name;
}

// The clips `selection` names: empty, the first; "all"; a number, that index; else the clip of that name.
std::vector<size_t> selected_clips(const nlohmann::json& animations, const std::string& selection,
                                   const std::string& file) {
    const size_t count = animations.is_array() ? animations.size() : 0;
    if (selection.empty()) return count > 0 ? std::vector<size_t>{0} : std::vector<size_t>{};
    if (count == 0) throw file_error(file, "has no animations to play (--animation " + shorten(selection) + ")");
    std::vector<size_t> all(count);
    for (size_t i = 0; i < count; ++i) all[i] = i;
    if (selection == "all") return all;
    if (selection.find_first_not_of("0123456789") == std::string::npos && selection.size() <= 9) {
        const size_t index = std::stoul(selection);
        if (index < count) return {index};
    }
    for (size_t i = 0; i < count; ++i)
        if (animations[i].is_object() && string_of(animations[i], "name") == selection) return {i};
    std::string cause = "no animation '";
    cause.append(shorten(selection)).append("' (it has ").append(std::to_string(count)).append(": ");
    for (size_t i = 0; i < count && i < 8; ++i)
        cause.append(i ? ", " : "").append(std::to_string(i)).append(" '").append(clip_name(animations, i)).append("'");
    cause.append(count > 8 ? ", ...; or all)" : "; or all)");
    throw file_error(file, cause);
}

}  // namespace

FileAnimation read_animations(const nlohmann::json& animations, const tinygltf::Model& model, const std::string& file,
                              const std::string& selection) {
    FileAnimation out;
    const std::vector<size_t> clips = selected_clips(animations, selection, file);
    if (clips.empty()) return out;
    size_t buffer_bytes = 0;
    for (const tinygltf::Buffer& buffer : model.buffers) buffer_bytes += buffer.data.size();
    out.key_floats_left = std::max(kMinKeyFloats, buffer_bytes);
    out.animation_count = animations.size();
    for (size_t i : clips)
        if (animations[i].is_object()) read_clip(animations[i], clip_name(animations, i), model, file, out);
    out.name =
        clips.size() == 1 ? clip_name(animations, clips[0]) : "all " + std::to_string(clips.size()) + " animations";
    if (out.malformed > kMalformedChannelsNamed)
        out.warnings.push_back(file_error(file, std::to_string(out.malformed - kMalformedChannelsNamed) +
                                                    " more malformed animation channels left out")
                                   .what());
    if (selection.empty() && out.animation_count > 1)
        out.warnings.push_back(file_error(file, "has " + std::to_string(out.animation_count) +
                                                    " animations; sequences and the viewer play the first, '" +
                                                    out.name + "' (--animation picks another, or all)")
                                   .what());
    return out;
}

AnimationRig::AnimationRig(FileAnimation animation, const tinygltf::Model& model, std::string file)
    : file_animation_(std::move(animation)), model_(model), file_(std::move(file)) {
    animation_.name = file_animation_.name;
    if (file_animation_.channels.empty()) return;
    keyed_.assign(model_.nodes.size(), false);
    weights_channel_.assign(model_.nodes.size(), -1);
    slot_of_.assign(model_.nodes.size(), -1);
    for (size_t c = 0; c < file_animation_.channels.size(); ++c) {
        const FileChannel& channel = file_animation_.channels[c];
        if (channel.weights)
            weights_channel_[size_t(channel.node)] = int32_t(c);  // with "all", the last clip keying them wins
        // glTF animates nodes given by translation, rotation and scale; a node with a matrix is drawn as given.
        else if (model_.nodes[size_t(channel.node)].matrix.size() != 16)
            keyed_[size_t(channel.node)] = true;
    }
}

AnimationRig::Place AnimationRig::enter(int node_index, const glm::mat4& local, Place parent) {
    if (keyed_.empty()) return {};
    const tinygltf::Node& node = model_.nodes[size_t(node_index)];
    AnimationNode placed;
    placed.parent = parent.slot;
    placed.matrix = local;
    placed.keyed = keyed_[size_t(node_index)];
    if (node.translation.size() == 3)
        placed.translation = glm::vec3(node.translation[0], node.translation[1], node.translation[2]);
    if (node.rotation.size() == 4)
        placed.rotation = glm::normalize(glm::quat(float(node.rotation[3]), float(node.rotation[0]),
                                                   float(node.rotation[1]), float(node.rotation[2])));
    if (node.scale.size() == 3) placed.scale = glm::vec3(node.scale[0], node.scale[1], node.scale[2]);
    const int32_t slot = int32_t(animation_.nodes.size());
    animation_.nodes.push_back(placed);
    slot_of_[size_t(node_index)] = slot;
    slot_moves_.push_back(parent.moves || placed.keyed);
    return {slot, slot_moves_.back()};
}

bool AnimationRig::weights_keyed(int node_index) const {
    return !weights_channel_.empty() && weights_channel_[size_t(node_index)] >= 0;
}

bool AnimationRig::moves(int node_index) const {
    if (slot_of_.empty()) return false;
    const int32_t slot = slot_of_[size_t(node_index)];
    return slot >= 0 && slot_moves_[size_t(slot)];
}

void AnimationRig::add_deformation(MeshDeformation deformation, int weights_node, const std::vector<int>& joints) {
    if (slot_of_.empty()) return;
    deformation.joints.clear();
    for (int joint : joints) deformation.joints.push_back(uint32_t(slot_of_[size_t(joint)]));
    deformation_weights_.push_back(weights_node >= 0 ? weights_channel_[size_t(weights_node)] : -1);
    animation_.deformations.push_back(std::move(deformation));
}

void AnimationRig::add_instance(uint32_t instance, Place place, const glm::mat4& local) {
    if (place.moves) animation_.instances.push_back({instance, uint32_t(place.slot), local});
}

void AnimationRig::set_camera(Place place) {
    if (place.moves) animation_.camera_node = place.slot;
}

void AnimationRig::add_light(uint32_t light, Place place) {
    if (place.moves) animation_.lights.push_back({light, uint32_t(place.slot)});
}

NodeAnimation AnimationRig::finish(std::vector<std::string>& warnings) {
    for (const std::string& warning : file_animation_.warnings) warnings.push_back(warning);
    const size_t total = file_animation_.channels.size() + file_animation_.unplayable + file_animation_.malformed;
    if (file_animation_.animation_count == 0) return {};
    // The nodes some recorded instance, light, the camera or a deformed mesh's joint hangs from or below: a channel
    // elsewhere moves nothing Prism draws (other cameras, empty nodes, joints of no drawn skin).
    std::vector<bool> carries(animation_.nodes.size(), false);
    auto carry = [&](int32_t slot) {
        for (; slot >= 0 && !carries[size_t(slot)]; slot = animation_.nodes[size_t(slot)].parent)
            carries[size_t(slot)] = true;
    };
    for (const AnimatedInstance& instance : animation_.instances) carry(int32_t(instance.node));
    for (const AnimatedLight& light : animation_.lights) carry(int32_t(light.node));
    carry(animation_.camera_node);
    for (const MeshDeformation& deformation : animation_.deformations)
        for (uint32_t joint : deformation.joints) carry(int32_t(joint));
    size_t played = 0;
    for (FileChannel& channel : file_animation_.channels) {
        if (channel.weights) continue;
        const int32_t slot = slot_of_.empty() ? -1 : slot_of_[size_t(channel.node)];
        if (slot < 0 || !carries[size_t(slot)] || !animation_.nodes[size_t(slot)].keyed) continue;
        channel.channel.node = uint32_t(slot);
        animation_.duration = std::max(animation_.duration, channel.channel.clip_seconds);
        animation_.channels.push_back(std::move(channel.channel));
        ++played;
    }
    // Each deformed mesh whose weights are keyed takes its channel (one copy per channel, shared by its meshes).
    std::vector<int32_t> copied(file_animation_.channels.size(), -1);
    for (size_t d = 0; d < animation_.deformations.size(); ++d) {
        const int32_t c = deformation_weights_[d];
        if (c < 0) continue;
        if (copied[size_t(c)] < 0) {
            copied[size_t(c)] = int32_t(animation_.weight_channels.size());
            const WeightChannel& channel = file_animation_.channels[size_t(c)].weight_channel;
            animation_.duration = std::max(animation_.duration, channel.clip_seconds);
            animation_.weight_channels.push_back(channel);
            ++played;
        }
        animation_.deformations[d].weight_channel = copied[size_t(c)];
    }
    const std::string named = "animation '" + animation_.name + "'";
    if (!animation_.plays()) {
        warnings.push_back(file_error(file_, named + " is not played: it moves no mesh Prism draws, no light and not "
                                                     "the camera (only other cameras, joints of no skinned mesh, or "
                                                     "animation pointers); the scene is drawn as its nodes place it")
                               .what());
        return {};
    }
    if (played < total)
        warnings.push_back(file_error(file_, named + ": " + std::to_string(total - played) + " of its " +
                                                 std::to_string(total) +
                                                 " channels are not played (other cameras, joints of no skinned "
                                                 "mesh, nodes with nothing Prism draws, animation pointers, nodes "
                                                 "given by a matrix)")
                               .what());
    return std::move(animation_);
}

}  // namespace prism::gltf
