#include "bench/query_rays.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <utility>

#include <glm/glm.hpp>

namespace prism::bench {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

RayQuery ray_from(glm::vec3 origin, glm::vec3 direction) {
    return RayQuery{{origin.x, origin.y, origin.z}, 0.0f, {direction.x, direction.y, direction.z}, kInfinity};
}

// A pinhole camera's ray through (px, py) of its image plane at distance 1, in units of the plane's half height.
struct Pinhole {
    glm::vec3 position, forward, right, up;
    float tan_half;
    RayQuery ray(float px, float py) const {
        return ray_from(position, glm::normalize(forward + (px * tan_half) * right + (py * tan_half) * up));
    }
};

Pinhole pinhole(glm::vec3 position, glm::vec3 target, glm::vec3 up_hint, float vertical_fov_degrees) {
    Pinhole p;
    p.position = position;
    p.forward = glm::normalize(target - position);
    p.right = glm::normalize(glm::cross(p.forward, up_hint));
    p.up = glm::cross(p.right, p.forward);
    p.tan_half = std::tan(glm::radians(vertical_fov_degrees) * 0.5f);
    return p;
}

}  // namespace

std::vector<RayQuery> scene_camera_rays(const Scene& scene, size_t count) {
    const Camera& camera = scene.camera;
    Pinhole view = pinhole(camera.position, camera.target, camera.up, camera.vertical_fov_degrees);
    size_t side = static_cast<size_t>(std::ceil(std::sqrt(double(count))));
    std::vector<RayQuery> rays;
    rays.reserve(count);
    for (size_t i = 0; i < count; ++i)
        rays.push_back(view.ray(2.0f * (float(i % side) + 0.5f) / float(side) - 1.0f,
                                1.0f - 2.0f * (float(i / side) + 0.5f) / float(side)));
    return rays;
}

std::vector<RayQuery> framing_camera_rays(const Scene& scene, uint32_t width, uint32_t height) {
    glm::vec3 lower(kInfinity), upper(-kInfinity);
    for (const Instance& instance : scene.instances)
        for (const glm::vec3& p : scene.meshes[instance.mesh].positions) {
            glm::vec3 world = glm::vec3(instance.transform * glm::vec4(p, 1.0f));
            lower = glm::min(lower, world);
            upper = glm::max(upper, world);
        }
    if (!(lower.x <= upper.x)) lower = upper = glm::vec3(0.0f);  // nothing to frame
    glm::vec3 centre = 0.5f * (lower + upper);
    glm::vec3 half = glm::max(0.5f * (upper - lower), glm::vec3(1e-6f));
    const float fov = 45.0f;
    float aspect = float(width) / float(height);
    float tan_half = std::tan(glm::radians(fov) * 0.5f);
    // Back from the box's front face until its height and width fit the view.
    float distance = half.z + std::max(half.y / tan_half, half.x / (tan_half * aspect));
    Pinhole view = pinhole(centre + glm::vec3(0.0f, 0.0f, distance), centre, glm::vec3(0.0f, 1.0f, 0.0f), fov);
    std::vector<RayQuery> rays;
    rays.reserve(size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            rays.push_back(view.ray((2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * aspect,
                                    1.0f - 2.0f * (float(y) + 0.5f) / float(height)));
    return rays;
}

namespace {

// A coordinate's cell of 10 bits along `axis` of the box [lower, lower + extent]; NaN (a ray file's NaN or infinite
// coordinates) goes to cell 0 rather than into an undefined conversion.
uint32_t cell10(float x, int axis, glm::vec3 lower, glm::vec3 extent) {
    float unit = (x - lower[axis]) / extent[axis];
    if (!(unit >= 0.0f)) return 0u;
    return static_cast<uint32_t>(std::min(unit, 1.0f) * 1023.0f);
}

// The Morton code of 10-bit cells: their bits interleaved from the top bit down, the first cell's bit the most
// significant of each group.
uint64_t morton(std::initializer_list<uint32_t> cells) {
    uint64_t key = 0;
    for (int bit = 9; bit >= 0; --bit)
        for (uint32_t c : cells) key = key << 1 | ((c >> bit) & 1u);
    return key;
}

// The box around the rays' origins.
std::pair<glm::vec3, glm::vec3> origin_bounds(const std::vector<RayQuery>& rays) {
    glm::vec3 lower(kInfinity), upper(-kInfinity);
    for (const RayQuery& r : rays) {
        glm::vec3 o(r.origin[0], r.origin[1], r.origin[2]);
        lower = glm::min(lower, o);
        upper = glm::max(upper, o);
    }
    return {lower, upper};
}

// The indices in ascending order of their keys, equal keys in index order.
std::vector<size_t> stable_order(const std::vector<uint64_t>& keys) {
    std::vector<size_t> order(keys.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&keys](size_t a, size_t b) { return keys[a] < keys[b]; });
    return order;
}

}  // namespace

std::vector<size_t> coherent_order(const std::vector<RayQuery>& rays) {
    auto [lower, upper] = origin_bounds(rays);
    glm::vec3 extent = glm::max(upper - lower, glm::vec3(1e-30f));
    std::vector<uint64_t> keys(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayQuery& r = rays[i];
        uint64_t octant =
            (r.direction[0] < 0.0f ? 1u : 0u) | (r.direction[1] < 0.0f ? 2u : 0u) | (r.direction[2] < 0.0f ? 4u : 0u);
        keys[i] = octant << 30 | morton({cell10(r.origin[2], 2, lower, extent), cell10(r.origin[1], 1, lower, extent),
                                         cell10(r.origin[0], 0, lower, extent)});
    }
    return stable_order(keys);
}

std::vector<size_t> two_point_order(const std::vector<RayQuery>& rays) {
    auto [lower, upper] = origin_bounds(rays);
    float length = 0.25f * glm::length(upper - lower);
    if (!(length > 0.0f)) length = 1.0f;  // one origin (a camera's rays): order by the direction alone
    lower -= glm::vec3(length);
    upper += glm::vec3(length);
    glm::vec3 extent = glm::max(upper - lower, glm::vec3(1e-30f));
    std::vector<uint64_t> keys(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        const RayQuery& r = rays[i];
        auto origin = [&](int axis) { return cell10(r.origin[axis], axis, lower, extent); };
        auto end = [&](int axis) { return cell10(r.origin[axis] + length * r.direction[axis], axis, lower, extent); };
        keys[i] = morton({origin(0), origin(1), origin(2), end(0), end(1), end(2)});
    }
    return stable_order(keys);
}

std::vector<RayQuery> diffuse_rays(const Scene& scene, const std::vector<RayQuery>& primary,
                                   const std::vector<RayHit>& hits, size_t count, uint32_t seed) {
    std::vector<size_t> hit_rays;
    for (size_t i = 0; i < hits.size() && i < primary.size(); ++i)
        if (hits[i].t < kInfinity) hit_rays.push_back(i);
    std::vector<RayQuery> rays;
    if (hit_rays.empty()) return rays;
    rays.reserve(count);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (size_t k = 0; rays.size() < count; ++k) {
        size_t i = hit_rays[k % hit_rays.size()];
        const RayHit& h = hits[i];
        const Mesh& mesh = scene.meshes[scene.instances[h.instance].mesh];
        const glm::mat4& m = scene.instances[h.instance].transform;
        glm::uvec3 tri = mesh.triangles[h.primitive];
        glm::vec3 a = glm::vec3(m * glm::vec4(mesh.positions[tri.x], 1.0f));
        glm::vec3 b = glm::vec3(m * glm::vec4(mesh.positions[tri.y], 1.0f));
        glm::vec3 c = glm::vec3(m * glm::vec4(mesh.positions[tri.z], 1.0f));
        glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        glm::vec3 incoming{primary[i].direction[0], primary[i].direction[1], primary[i].direction[2]};
        if (glm::dot(n, incoming) > 0.0f) n = -n;
        glm::vec3 p = a * (1.0f - h.u - h.v) + b * h.u + c * h.v;
        // Cosine-weighted hemisphere around n.
        float r1 = uniform(rng), r2 = uniform(rng);
        float phi = 2.0f * 3.14159265f * r1, radius = std::sqrt(r2);
        glm::vec3 t = glm::normalize(std::abs(n.x) > 0.9f ? glm::cross(n, glm::vec3(0, 1, 0))
                                                          : glm::cross(n, glm::vec3(1, 0, 0)));
        glm::vec3 s = glm::cross(n, t);
        glm::vec3 d =
            glm::normalize(t * (radius * std::cos(phi)) + s * (radius * std::sin(phi)) + n * std::sqrt(1.0f - r2));
        float scale = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), 1.0f});
        rays.push_back(ray_from(p + n * (1e-4f * scale), d));
    }
    return rays;
}

Agreement compare_hits(const std::vector<RayHit>& a, const std::vector<RayHit>& b) {
    Agreement result;
    result.rays = std::min(a.size(), b.size());
    for (size_t i = 0; i < result.rays; ++i) {
        bool a_miss = !(a[i].t < kInfinity);
        bool b_miss = !(b[i].t < kInfinity);
        if (a_miss || b_miss) {
            result.same += a_miss == b_miss;
            continue;
        }
        if (a[i].instance == b[i].instance && a[i].primitive == b[i].primitive) {
            ++result.same;
            if (std::abs(a[i].t - b[i].t) > 1e-4f * std::max(std::abs(a[i].t), std::abs(b[i].t)))
                ++result.t_outside_tolerance;
        }
    }
    return result;
}

}  // namespace prism::bench
