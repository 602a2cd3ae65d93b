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

}  // namespace

void append_node_animation(NodeAnimation& into, const NodeAnimation& part, uint32_t first_instance,
                           const glm::mat4& placement) {
    if (!part.plays() || part.instances.empty()) return;
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
}

glm::vec4 sample_channel(const AnimationChannel& channel, float seconds) {
    const std::vector<float>& times = channel.times;
    const bool cubic = channel.interpolation == AnimationInterpolation::CubicSpline;
    const bool rotation = channel.path == AnimationPath::Rotation;
    auto value = [&](size_t key) { return channel.values[cubic ? 3 * key + 1 : key]; };
    auto finish = [&](const glm::vec4& v) { return rotation ? normalized_rotation(v) : v; };
    if (times.empty()) return rotation ? glm::vec4(0.0f, 0.0f, 0.0f, 1.0f) : glm::vec4(0.0f);
    // Before the first key and after the last the channel holds its end values (glTF 2.0, Appendix C).
    if (!(seconds > times.front())) return finish(value(0));
    if (seconds >= times.back()) return finish(value(times.size() - 1));
    const size_t next = size_t(std::upper_bound(times.begin(), times.end(), seconds) - times.begin());
    const size_t key = next - 1;
    const float interval = times[next] - times[key];
    const float u = interval > 0.0f ? (seconds - times[key]) / interval : 0.0f;
    switch (channel.interpolation) {
        case AnimationInterpolation::Step: return finish(value(key));
        case AnimationInterpolation::Linear:
            if (rotation) return as_vec4(glm::normalize(glm::slerp(as_quat(value(key)), as_quat(value(next)), u)));
            return glm::mix(value(key), value(next), u);
        case AnimationInterpolation::CubicSpline: {
            // Hermite between the two keys: the key's out-tangent and the next key's in-tangent, scaled by the
            // interval (the spec's tangents are per second).
            const float u2 = u * u, u3 = u2 * u;
            const glm::vec4 out_tangent = channel.values[3 * key + 2], in_tangent = channel.values[3 * next];
            return finish((2.0f * u3 - 3.0f * u2 + 1.0f) * value(key) + interval * (u3 - 2.0f * u2 + u) * out_tangent +
                          (-2.0f * u3 + 3.0f * u2) * value(next) + interval * (u3 - u2) * in_tangent);
        }
    }
    return finish(value(key));
}

std::vector<glm::mat4> node_world_transforms(const NodeAnimation& animation, double seconds) {
    std::vector<AnimationNode> posed = animation.nodes;
    for (const AnimationChannel& channel : animation.channels) {
        double t = channel.clip_seconds > 0.0 ? std::fmod(seconds, channel.clip_seconds) : 0.0;
        if (t < 0.0) t += channel.clip_seconds;
        AnimationNode& node = posed[channel.node];
        const glm::vec4 v = sample_channel(channel, float(t));
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
        bool finite = true;
        for (int column = 0; column < 4; ++column)
            for (int row = 0; row < 4; ++row) finite = finite && std::isfinite(moved[column][row]);
        if (finite) transforms.at(instance.instance) = moved;
    }
}

}  // namespace prism
