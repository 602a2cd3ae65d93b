#include "core/scene/node_animation.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace prism {
namespace {

glm::quat as_quat(const glm::vec4& v) { return glm::quat(v.w, v.x, v.y, v.z); }
glm::vec4 as_vec4(const glm::quat& q) { return {q.x, q.y, q.z, q.w}; }

glm::vec4 normalized_rotation(const glm::vec4& v) {
    const float length = glm::length(v);
    return length > 0.0f ? v / length : glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
}

// Where `seconds` falls among a channel's key times: between `key` and `next` at fraction `u` of their `interval`,
// or held at the first or last key (glTF 2.0, Appendix C: before the first key and after the last the channel
// holds its end values), where key == next.
struct KeySpan {
    size_t key = 0, next = 0;
    float u = 0.0f, interval = 0.0f;
};

KeySpan locate(const std::vector<float>& times, float seconds) {
    if (!(seconds > times.front())) return {};
    if (seconds >= times.back()) return {times.size() - 1, times.size() - 1};
    const size_t next = size_t(std::upper_bound(times.begin(), times.end(), seconds) - times.begin());
    const size_t key = next - 1;
    const float interval = times[next] - times[key];
    return {key, next, interval > 0.0f ? (seconds - times[key]) / interval : 0.0f, interval};
}

// Hermite between two keys: the key's out-tangent and the next key's in-tangent, scaled by the interval (the spec's
// tangents are per second).
template <typename T>
T hermite(const T& value, const T& out_tangent, const T& next_value, const T& in_tangent, float u, float interval) {
    const float u2 = u * u, u3 = u2 * u;
    return (2.0f * u3 - 3.0f * u2 + 1.0f) * value + interval * (u3 - 2.0f * u2 + u) * out_tangent +
           (-2.0f * u3 + 3.0f * u2) * next_value + interval * (u3 - u2) * in_tangent;
}

// A channel's time within its clip, which loops over its own length.
float clip_time(double seconds, double clip_seconds) {
    double t = clip_seconds > 0.0 ? std::fmod(seconds, clip_seconds) : 0.0;
    if (t < 0.0) t += clip_seconds;
    return float(t);
}

bool finite(const glm::mat4& m) {
    for (int column = 0; column < 4; ++column)
        for (int row = 0; row < 4; ++row)
            if (!std::isfinite(m[column][row])) return false;
    return true;
}

template <typename V>
bool all_finite(const std::vector<V>& values) {
    for (const V& v : values)
        for (int i = 0; i < V::length(); ++i)
            if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace

void append_node_animation(NodeAnimation& into, const NodeAnimation& part, uint32_t first_instance,
                           uint32_t first_light, const glm::mat4& placement) {
    if (!part.plays()) return;
    into.name = into.name.empty() ? part.name : into.name + ", " + part.name;
    into.duration = std::max(into.duration, part.duration);
    const auto root = int32_t(into.nodes.size());
    AnimationNode placed;
    placed.matrix = placement;
    into.nodes.push_back(placed);
    const auto offset = uint32_t(into.nodes.size());
    for (AnimationNode node : part.nodes) {
        node.parent = node.parent >= 0 ? node.parent + int32_t(offset) : root;
        into.nodes.push_back(node);
    }
    for (AnimationChannel channel : part.channels) {
        channel.node += offset;
        into.channels.push_back(std::move(channel));
    }
    for (AnimatedInstance instance : part.instances) {
        instance.instance += first_instance;
        instance.node += offset;
        into.instances.push_back(instance);
    }
    for (AnimatedLight light : part.lights) {
        light.light += first_light;
        light.node += offset;
        into.lights.push_back(light);
    }
    const auto weight_offset = int32_t(into.weight_channels.size());
    into.weight_channels.insert(into.weight_channels.end(), part.weight_channels.begin(), part.weight_channels.end());
    for (MeshDeformation deformation : part.deformations) {
        const bool placed_before = std::any_of(into.deformations.begin(), into.deformations.end(),
                                               [&](const MeshDeformation& d) { return d.mesh == deformation.mesh; });
        if (placed_before) continue;
        for (uint32_t& joint : deformation.joints) joint += offset;
        if (deformation.weight_channel >= 0) deformation.weight_channel += weight_offset;
        // The mesh is in the model's space, and its instances carry the placement.
        deformation.space_node = deformation.space_node >= 0 ? deformation.space_node + int32_t(offset) : root;
        into.deformations.push_back(std::move(deformation));
    }
}

glm::vec4 sample_channel(const AnimationChannel& channel, float seconds) {
    const std::vector<float>& times = channel.times;
    const bool cubic = channel.interpolation == AnimationInterpolation::CubicSpline;
    const bool rotation = channel.path == AnimationPath::Rotation;
    auto value = [&](size_t key) { return channel.values[cubic ? 3 * key + 1 : key]; };
    auto finish = [&](const glm::vec4& v) { return rotation ? normalized_rotation(v) : v; };
    if (times.empty()) return rotation ? glm::vec4(0.0f, 0.0f, 0.0f, 1.0f) : glm::vec4(0.0f);
    const KeySpan span = locate(times, seconds);
    if (span.key == span.next) return finish(value(span.key));
    switch (channel.interpolation) {
        case AnimationInterpolation::Step: return finish(value(span.key));
        case AnimationInterpolation::Linear:
            if (rotation)
                return as_vec4(glm::normalize(glm::slerp(as_quat(value(span.key)), as_quat(value(span.next)), span.u)));
            return glm::mix(value(span.key), value(span.next), span.u);
        case AnimationInterpolation::CubicSpline:
            return finish(hermite(value(span.key), channel.values[3 * span.key + 2], value(span.next),
                                  channel.values[3 * span.next], span.u, span.interval));
    }
    return finish(value(span.key));
}

std::vector<float> sample_weights(const WeightChannel& channel, float seconds) {
    const size_t width = channel.width;
    std::vector<float> weights(width, 0.0f);
    if (channel.times.empty()) return weights;
    const bool cubic = channel.interpolation == AnimationInterpolation::CubicSpline;
    auto value = [&](size_t key, size_t i) { return channel.values[(cubic ? 3 * key + 1 : key) * width + i]; };
    const KeySpan span = locate(channel.times, seconds);
    for (size_t i = 0; i < width; ++i) {
        if (span.key == span.next || channel.interpolation == AnimationInterpolation::Step)
            weights[i] = value(span.key, i);
        else if (!cubic)
            weights[i] = value(span.key, i) + (value(span.next, i) - value(span.key, i)) * span.u;
        else
            weights[i] = hermite(value(span.key, i), channel.values[(3 * span.key + 2) * width + i],
                                 value(span.next, i), channel.values[3 * span.next * width + i], span.u, span.interval);
    }
    return weights;
}

std::vector<glm::mat4> node_world_transforms(const NodeAnimation& animation, double seconds) {
    std::vector<AnimationNode> posed = animation.nodes;
    for (const AnimationChannel& channel : animation.channels) {
        AnimationNode& node = posed[channel.node];
        const glm::vec4 v = sample_channel(channel, clip_time(seconds, channel.clip_seconds));
        switch (channel.path) {
            case AnimationPath::Translation: node.translation = glm::vec3(v); break;
            case AnimationPath::Rotation: node.rotation = as_quat(v); break;
            case AnimationPath::Scale: node.scale = glm::vec3(v); break;
        }
    }
    // Parents come before their children, so one pass composes every world transform.
    std::vector<glm::mat4> world(posed.size());
    for (size_t i = 0; i < posed.size(); ++i) {
        const AnimationNode& node = posed[i];
        const glm::mat4 local = node.keyed ? glm::translate(glm::mat4(1.0f), node.translation) *
                                                 glm::mat4_cast(node.rotation) * glm::scale(glm::mat4(1.0f), node.scale)
                                           : node.matrix;
        world[i] = node.parent >= 0 ? world[size_t(node.parent)] * local : local;
    }
    return world;
}

void apply_node_animation(const NodeAnimation& animation, double seconds, std::vector<glm::mat4>& transforms) {
    if (!animation.plays() || animation.instances.empty()) return;
    const std::vector<glm::mat4> world = node_world_transforms(animation, seconds);
    // Finite keys can still compose to inf (scales of 1e30 on nested nodes): such an instance keeps the transform it
    // had, so the BVH and the kernels never see a non-finite one.
    for (const AnimatedInstance& instance : animation.instances) {
        const glm::mat4 moved = world[instance.node] * instance.local;
        if (finite(moved)) transforms.at(instance.instance) = moved;
    }
}

std::vector<DeformedVertices> deformed_meshes_at(const NodeAnimation& animation, double seconds) {
    std::vector<DeformedVertices> meshes(animation.deformations.size());
    if (!animation.plays() || animation.deformations.empty()) return meshes;
    const std::vector<glm::mat4> world = node_world_transforms(animation, seconds);
    for (size_t d = 0; d < meshes.size(); ++d) {
        const MeshDeformation& deformation = animation.deformations[d];
        DeformedVertices posed = deformation.rest;
        if (deformation.weight_channel >= 0) {
            const WeightChannel& channel = animation.weight_channels[size_t(deformation.weight_channel)];
            morph_vertices(posed, deformation.targets,
                           sample_weights(channel, clip_time(seconds, channel.clip_seconds)));
        } else {
            morph_vertices(posed, deformation.targets, deformation.weights);
        }
        if (!deformation.joints.empty()) {
            const glm::mat4 space =
                deformation.space_node >= 0 ? glm::inverse(world[size_t(deformation.space_node)]) : glm::mat4(1.0f);
            std::vector<glm::mat4> joints(deformation.joints.size());
            for (size_t j = 0; j < joints.size(); ++j)
                joints[j] = space * world[deformation.joints[j]] * deformation.inverse_bind[j];
            skin_vertices(posed, deformation.influences, joints);
        }
        if (all_finite(posed.positions) && all_finite(posed.normals) && all_finite(posed.tangents))
            meshes[d] = std::move(posed);
    }
    return meshes;
}

}  // namespace prism
