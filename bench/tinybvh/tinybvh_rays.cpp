// tinybvh_rays: tinybvh's GPU traversal (issue 19's baseline: its BVH_GPU "Aila-Laine" layout from its SBVH
// build, traced by its own OpenCL kernel `batch_ailalaine`) on the ray sets `prism rays --bench` traces, on the same
// card, so that the two are compared ray for ray rather than against figures measured on other rays.
//
// Built only with -DPRISM_TINYBVH_DIR=<a tinybvh checkout> (tinybvh is not a dependency of Prism). The rays are
// bench/query_rays.h's (the same width, height and seed give the same rays as `prism rays --bench`); the hits are
// compared with Embree's. Timing follows tinybvh's speed test: the rays uploaded once, launches of one work-item
// per ray in groups of 64 back to back, each timed by its OpenCL event; one untimed launch first, then `--runs`
// timed ones, median. The program is built with tinybvh's own options for NVIDIA (tiny_ocl.h: OpenCL 2.0,
// -cl-fast-relaxed-math, -cl-nv-opt-level=9, ISNVIDIA defined); --math replaces its fast-math options, to trace
// with the IEEE arithmetic Prism's kernels keep (docs/fairness.md).
//   tinybvh_rays --scene mesh.ply [--width 1920 --height 1080] [--runs 21] [--seed 7] [--json out.json]
#define CL_TARGET_OPENCL_VERSION 300
#include <CL/cl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#define TINYBVH_IMPLEMENTATION
#include "tiny_bvh.h"

#include "bench/bench_json.h"
#include "bench/embree_oracle.h"
#include "bench/query_rays.h"
#include "core/loaders/scene_loader.h"
#include "core/render/device_scene.h"
#include "core/util/error.h"
#include "core/util/median.h"

namespace {

using namespace prism;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr uint32_t kNoHit = 0xffffffffu;

void check(cl_int status, const char* what) {
    if (status != CL_SUCCESS) throw Error(std::string("OpenCL: ") + what + " failed (" + std::to_string(status) + ")");
}

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string device_string(cl_device_id device, cl_device_info what) {
    size_t size = 0;
    clGetDeviceInfo(device, what, 0, nullptr, &size);
    std::string value(size, '\0');
    clGetDeviceInfo(device, what, size, value.data(), nullptr);
    while (!value.empty() && value.back() == '\0') value.pop_back();
    return value;
}

// The first GPU of the first platform whose name has "NVIDIA", else the first GPU anywhere, else any device (PoCL's
// CPU device, to try the program out without a GPU).
cl_device_id pick_device() {
    cl_uint count = 0;
    check(clGetPlatformIDs(0, nullptr, &count), "clGetPlatformIDs");
    std::vector<cl_platform_id> platforms(count);
    check(clGetPlatformIDs(count, platforms.data(), nullptr), "clGetPlatformIDs");
    cl_device_id fallback = nullptr;
    for (cl_platform_id platform : platforms) {
        char name[256] = {};
        clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof name, name, nullptr);
        cl_device_id device = nullptr;
        if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_GPU, 1, &device, nullptr) == CL_SUCCESS) {
            if (std::strstr(name, "NVIDIA")) return device;
            if (!fallback) fallback = device;
        }
    }
    if (!fallback && count > 0) clGetDeviceIDs(platforms[0], CL_DEVICE_TYPE_ALL, 1, &fallback, nullptr);
    if (!fallback) throw Error("no OpenCL device");
    return fallback;
}

struct Gpu {
    cl_device_id device = nullptr;
    cl_context context = nullptr;
    cl_command_queue queue = nullptr;
    cl_kernel kernel = nullptr;
};

// tinybvh's own build options for the device (tiny_ocl.h); `math`, when not empty, replaces its
// "-cl-fast-relaxed-math -cl-single-precision-constant" ("none": neither).
Gpu open_gpu(const std::string& kernel_dir, const std::string& math, const std::string& binary_path) {
    Gpu gpu;
    cl_int status = CL_SUCCESS;
    gpu.device = pick_device();
    gpu.context = clCreateContext(nullptr, 1, &gpu.device, nullptr, nullptr, &status);
    check(status, "clCreateContext");
    cl_queue_properties properties[] = {CL_QUEUE_PROPERTIES, CL_QUEUE_PROFILING_ENABLE, 0};
    gpu.queue = clCreateCommandQueueWithProperties(gpu.context, gpu.device, properties, &status);
    check(status, "clCreateCommandQueueWithProperties");
    bool nvidia = device_string(gpu.device, CL_DEVICE_VENDOR).find("NVIDIA") != std::string::npos;
    std::string source = std::string(nvidia ? "#define ISNVIDIA\n" : "") + read_text(kernel_dir + "/traverse.cl");
    const char* text = source.c_str();
    cl_program program = clCreateProgramWithSource(gpu.context, 1, &text, nullptr, &status);
    check(status, "clCreateProgramWithSource");
    std::string math_options = math.empty()     ? "-cl-fast-relaxed-math -cl-single-precision-constant"
                               : math == "none" ? ""
                                                : math;
    std::string options = "-I " + kernel_dir + " -cl-std=CL2.0 -cl-strict-aliasing " + math_options;
    if (nvidia) options += " -cl-nv-opt-level=9";
    if (clBuildProgram(program, 1, &gpu.device, options.c_str(), nullptr, nullptr) != CL_SUCCESS) {
        size_t size = 0;
        clGetProgramBuildInfo(program, gpu.device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
        std::string log(size, '\0');
        clGetProgramBuildInfo(program, gpu.device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
        throw Error(kernel_dir + "/traverse.cl: build failed: " + log.substr(0, 2000));
    }
    if (!binary_path.empty()) {
        // The program's binary (PTX on NVIDIA's platform), for `ptxas -v` to tell its registers: NVIDIA's OpenCL
        // reports none.
        size_t size = 0;
        check(clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr), "clGetProgramInfo");
        std::string binary(size, '\0');
        unsigned char* data = reinterpret_cast<unsigned char*>(binary.data());
        check(clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof data, &data, nullptr), "clGetProgramInfo");
        std::ofstream(binary_path, std::ios::binary) << binary;
    }
    gpu.kernel = clCreateKernel(program, "batch_ailalaine", &status);
    check(status, "clCreateKernel(batch_ailalaine)");
    return gpu;
}

cl_mem device_buffer(const Gpu& gpu, size_t bytes, const void* data) {
    cl_int status = CL_SUCCESS;
    cl_mem buffer = clCreateBuffer(gpu.context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0),
                                   std::max<size_t>(bytes, 16), const_cast<void*>(data), &status);
    check(status, "clCreateBuffer");
    return buffer;
}

// tinybvh's GPU ray: O, D, 1/D as float4 (48 bytes), then the hit (t, u, v, triangle index) the kernel writes.
struct GpuRay {
    float o[4], d[4], rd[4], hit[4];
};

// The tree tinybvh's kernel walks, in its BVH_GPU form (node 0 the root; a node holds its two children's boxes, or
// is a leaf of triCount triangles from firstTri in `indices`), with the triangle soup `vertices` its indices name.
struct GpuTree {
    std::vector<tinybvh::BVH_GPU::BVHNode> nodes;
    std::vector<uint32_t> indices;
    std::vector<tinybvh::bvhvec4> vertices;
    std::vector<uint32_t> primitive_of_triangle;  // soup triangle -> primitive (file order)
};

// tinybvh's own: BVH_GPU from BuildHQ (SBVH) over the soup in file order.
GpuTree tinybvh_tree(const std::vector<tinybvh::bvhvec4>& soup) {
    const uint32_t triangles = uint32_t(soup.size() / 3);
    tinybvh::BVH_GPU bvh;
    bvh.BuildHQ(soup.data(), triangles);
    GpuTree tree;
    tree.nodes.assign(bvh.bvhNode, bvh.bvhNode + bvh.usedNodes);
    tree.indices.assign(bvh.bvh.primIdx, bvh.bvh.primIdx + bvh.bvh.idxCount);
    tree.vertices = soup;
    for (uint32_t t = 0; t < triangles; ++t) tree.primitive_of_triangle.push_back(t);
    return tree;
}

// Prism's: the stack layout's tree as `prism rays --bench` builds it (default options), each node as a BVH_GPU node
// (an interior node holds its child pair's boxes), node 0 the mesh's root; `soup` (file order) put in Prism's triangle
// order, so a leaf's triangles are its slots.
GpuTree prism_tree(const Scene& scene, const std::vector<tinybvh::bvhvec4>& soup) {
    DeviceScene device = build_device_scene(scene, BvhBuildOptions{});
    const uint32_t root = device.instances[0].root;
    auto index = [root](uint32_t node) { return node == root ? 0u : node == 0u ? root : node; };
    auto as_uint = [](float f) {
        uint32_t u = 0;
        std::memcpy(&u, &f, sizeof u);
        return u;
    };
    GpuTree tree;
    tree.nodes.resize(device.nodes.size());
    std::vector<uint32_t> stack{root};
    while (!stack.empty()) {
        uint32_t n = stack.back();
        stack.pop_back();
        const BvhNode& node = device.nodes[n];
        uint32_t first = as_uint(node.lower.w), count = as_uint(node.upper.w);
        tinybvh::BVH_GPU::BVHNode& out = tree.nodes[index(n)];
        out = {};
        if (count > 0) {
            out.triCount = count;
            out.firstTri = first;
            continue;
        }
        const BvhNode& a = device.nodes[first];
        const BvhNode& b = device.nodes[first + 1];
        out.lmin = tinybvh::bvhvec3(a.lower.x, a.lower.y, a.lower.z);
        out.lmax = tinybvh::bvhvec3(a.upper.x, a.upper.y, a.upper.z);
        out.rmin = tinybvh::bvhvec3(b.lower.x, b.lower.y, b.lower.z);
        out.rmax = tinybvh::bvhvec3(b.upper.x, b.upper.y, b.upper.z);
        out.left = index(first);
        out.right = index(first + 1);
        stack.push_back(first);
        stack.push_back(first + 1);
    }
    for (uint32_t slot = 0; slot < device.triangles.size(); ++slot) {
        uint32_t primitive = as_uint(device.triangles[slot].v0.w);
        tree.indices.push_back(slot);
        tree.primitive_of_triangle.push_back(primitive);
        tree.vertices.insert(tree.vertices.end(), soup.begin() + 3 * primitive, soup.begin() + 3 * primitive + 3);
    }
    return tree;
}

// The tree's SAH cost with a node visit and a triangle test costing 1 each, relative to the root's area; nodes
// and leaves reachable from the root counted.
struct TreeShape {
    double sah = 0.0;
    size_t interior = 0, leaves = 0, leaf_triangles = 0;
};

TreeShape tree_shape(const GpuTree& tree) {
    auto area = [](const tinybvh::bvhvec3& lo, const tinybvh::bvhvec3& hi) {
        tinybvh::bvhvec3 e = hi - lo;
        return double(e.x) * e.y + double(e.y) * e.z + double(e.z) * e.x;
    };
    struct Item {
        uint32_t node;
        double area;
    };
    const auto& root = tree.nodes[0];
    double root_area = area(tinybvh::tinybvh_min(root.lmin, root.rmin), tinybvh::tinybvh_max(root.lmax, root.rmax));
    TreeShape shape;
    std::vector<Item> stack{{0u, root_area}};
    while (!stack.empty()) {
        Item item = stack.back();
        stack.pop_back();
        const auto& node = tree.nodes[item.node];
        if (node.triCount > 0) {
            shape.leaves += 1;
            shape.leaf_triangles += node.triCount;
            shape.sah += item.area / root_area * node.triCount;
            continue;
        }
        shape.interior += 1;
        shape.sah += item.area / root_area;
        stack.push_back({node.left, area(node.lmin, node.lmax)});
        stack.push_back({node.right, area(node.rmin, node.rmax)});
    }
    return shape;
}

struct SetResult {
    std::vector<double> ms;
    std::vector<RayHit> hits;
};

// One set: uploaded once, one untimed launch, then `runs` timed ones back to back (tinybvh's speed test).
SetResult trace_set(const Gpu& gpu, const GpuTree& tree, cl_mem nodes, cl_mem indices, cl_mem vertices,
                    const std::vector<RayQuery>& rays, uint32_t runs) {
    const size_t group = 64;
    size_t padded = (rays.size() + group - 1) / group * group;
    std::vector<GpuRay> gpu_rays(padded);
    for (size_t i = 0; i < padded; ++i) {
        // The padding repeats the last ray: its launch's extra work-items trace what it does.
        const RayQuery& q = rays[std::min(i, rays.size() - 1)];
        tinybvh::Ray ray(tinybvh::bvhvec3(q.origin[0], q.origin[1], q.origin[2]),
                         tinybvh::bvhvec3(q.direction[0], q.direction[1], q.direction[2]), 1e30f);
        GpuRay& g = gpu_rays[i];
        std::memcpy(g.o, &ray.O, sizeof g.o);
        std::memcpy(g.d, &ray.D, sizeof g.d);
        std::memcpy(g.rd, &ray.rD, sizeof g.rd);
        std::fill(g.hit, g.hit + 4, 0.0f);
    }
    cl_mem buffer = device_buffer(gpu, padded * sizeof(GpuRay), gpu_rays.data());
    cl_mem arguments[4] = {nodes, indices, vertices, buffer};
    for (cl_uint a = 0; a < 4; ++a)
        check(clSetKernelArg(gpu.kernel, a, sizeof(cl_mem), &arguments[a]), "clSetKernelArg");
    SetResult result;
    for (uint32_t launch = 0; launch <= runs; ++launch) {
        cl_event event = nullptr;
        check(clEnqueueNDRangeKernel(gpu.queue, gpu.kernel, 1, nullptr, &padded, &group, 0, nullptr, &event),
              "clEnqueueNDRangeKernel");
        check(clWaitForEvents(1, &event), "clWaitForEvents");
        cl_ulong start = 0, end = 0;
        clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr);
        clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr);
        clReleaseEvent(event);
        if (launch > 0) result.ms.push_back(double(end - start) * 1e-6);
    }
    check(clEnqueueReadBuffer(gpu.queue, buffer, CL_TRUE, 0, padded * sizeof(GpuRay), gpu_rays.data(), 0, nullptr,
                              nullptr),
          "clEnqueueReadBuffer");
    clReleaseMemObject(buffer);
    for (size_t i = 0; i < rays.size(); ++i) {
        const float* h = gpu_rays[i].hit;
        uint32_t triangle = 0;
        std::memcpy(&triangle, &h[3], sizeof triangle);
        bool hit = h[0] < 1e30f;
        result.hits.push_back(hit ? RayHit{h[0], 0u, tree.primitive_of_triangle.at(triangle), h[1], h[2]}
                                  : RayHit{kInfinity, kNoHit, kNoHit, 0.0f, 0.0f});
    }
    return result;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app("tinybvh's GPU traversal on prism rays --bench's ray sets (see the source's header)");
    std::string scene_path, json_path, kernel_dir = PRISM_TINYBVH_DIR, math, tree_name = "tinybvh", binary_path;
    uint32_t width = 1920, height = 1080, runs = 21, seed = 7;
    app.add_option("--scene", scene_path, "one mesh (.ply, .ply.gz, ...)")->required();
    app.add_option("--width", width)->capture_default_str();
    app.add_option("--height", height)->capture_default_str();
    app.add_option("--runs", runs, "timed launches after one untimed")->capture_default_str();
    app.add_option("--seed", seed, "of the diffuse rays")->capture_default_str();
    app.add_option("--kernels", kernel_dir, "folder of tinybvh's traverse.cl")->capture_default_str();
    app.add_option("--math", math,
                   "options replacing tinybvh's -cl-fast-relaxed-math -cl-single-precision-constant (none: neither)");
    app.add_option("--tree", tree_name, "the tree the kernel walks: tinybvh's (BuildHQ) or prism's (stack layout)")
        ->check(CLI::IsMember({"tinybvh", "prism"}))
        ->capture_default_str();
    app.add_option("--program-binary", binary_path, "write the built program's binary (PTX on NVIDIA) here");
    app.add_option("--json", json_path);
    CLI11_PARSE(app, argc, argv);
    try {
        Scene scene = load_scene(scene_path);
        if (scene.instances.size() != 1) throw Error(scene_path + ": one mesh instance expected");
        const Mesh& mesh = scene.meshes[scene.instances[0].mesh];
        const glm::mat4& m = scene.instances[0].transform;
        // tinybvh's triangle soup in file order, so its triangle index is the primitive index.
        std::vector<tinybvh::bvhvec4> soup;
        for (const glm::uvec3& t : mesh.triangles)
            for (uint32_t v : {t.x, t.y, t.z}) {
                glm::vec4 p = m * glm::vec4(mesh.positions[v], 1.0f);
                soup.push_back(tinybvh::bvhvec4(p.x, p.y, p.z, 0.0f));
            }
        const uint32_t triangles = uint32_t(mesh.triangles.size());
        GpuTree tree = tree_name == "prism" ? prism_tree(scene, soup) : tinybvh_tree(soup);
        TreeShape shape = tree_shape(tree);

        oracle::EmbreeScene embree(scene);
        std::vector<RayQuery> primary = bench::framing_camera_rays(scene, width, height);
        std::vector<RayHit> primary_reference = embree.intersect1(primary);
        size_t hits = 0;
        for (const RayHit& h : primary_reference) hits += h.t < kInfinity;
        std::vector<RayQuery> diffuse = bench::diffuse_rays(scene, primary, primary_reference, hits, seed);
        std::vector<RayHit> diffuse_reference = embree.intersect1(diffuse);

        Gpu gpu = open_gpu(kernel_dir, math, binary_path);
        cl_mem nodes = device_buffer(gpu, tree.nodes.size() * sizeof(tree.nodes[0]), tree.nodes.data());
        cl_mem indices = device_buffer(gpu, tree.indices.size() * sizeof(uint32_t), tree.indices.data());
        cl_mem vertices = device_buffer(gpu, tree.vertices.size() * sizeof(tinybvh::bvhvec4), tree.vertices.data());

        nlohmann::json result = bench::result_header();
        result["kind"] = "ray_queries_tinybvh";
        result["scene"] = scene_path;
        result["triangles"] = triangles;
        result["tinybvh"] = {
            {"version", std::to_string(TINY_BVH_VERSION_MAJOR) + "." + std::to_string(TINY_BVH_VERSION_MINOR) + "." +
                            std::to_string(TINY_BVH_VERSION_SUB)},
            {"layout", "BVH_GPU (Aila-Laine 64-byte nodes)"},
            {"kernel", "batch_ailalaine (traverse_bvh2.cl)"}};
        result["tree"] = {
            {"built_by", tree_name == "prism" ? "Prism (stack layout, default options)" : "tinybvh BuildHQ (SBVH)"},
            {"interior_nodes", shape.interior},
            {"leaves", shape.leaves},
            {"leaf_triangles", shape.leaf_triangles},
            {"sah_cost", shape.sah},
            {"sah_cost_terms", "node visit 1, triangle test 1, areas relative to the root's"}};
        result["device"] = device_string(gpu.device, CL_DEVICE_NAME);
        result["driver"] = device_string(gpu.device, CL_DRIVER_VERSION);
        result["api_version"] = device_string(gpu.device, CL_DEVICE_VERSION);
        result["settings"] = {{"width", width},
                              {"height", height},
                              {"runs", runs},
                              {"seed", seed},
                              {"math_options", math.empty() ? "tinybvh's" : math},
                              {"time",
                               "kernel launch, OpenCL events, median of runs after one untimed launch; "
                               "rays uploaded once"}};
        result["reference"] = "Embree rtcIntersect1";
        std::printf("%s tinybvh %s kernel on %s's tree (SAH %.2f, %zu leaves) on %s:", scene_path.c_str(),
                    result["tinybvh"]["version"].get<std::string>().c_str(), tree_name.c_str(), shape.sah, shape.leaves,
                    result["device"].get<std::string>().c_str());
        struct Named {
            const char* name;
            const std::vector<RayQuery>& rays;
            const std::vector<RayHit>& reference;
        } sets[] = {{"primary", primary, primary_reference}, {"diffuse", diffuse, diffuse_reference}};
        for (const Named& set : sets) {
            SetResult traced = trace_set(gpu, tree, nodes, indices, vertices, set.rays, runs);
            bench::Agreement agreement = bench::compare_hits(traced.hits, set.reference);
            double mid = median(traced.ms);
            result[set.name] = {{"rays", set.rays.size()},
                                {"median_ms", mid},
                                {"min_ms", *std::min_element(traced.ms.begin(), traced.ms.end())},
                                {"max_ms", *std::max_element(traced.ms.begin(), traced.ms.end())},
                                {"mrays_per_s", double(set.rays.size()) / (mid * 1e3)},
                                {"agreement", agreement.fraction()},
                                {"t_outside_tolerance", agreement.t_outside_tolerance}};
            std::printf("  %s %zu rays %.3f ms %.1f Mrays/s (%.4f%% agree)", set.name, set.rays.size(), mid,
                        double(set.rays.size()) / (mid * 1e3), 100.0 * agreement.fraction());
        }
        std::printf("\n");
        if (!json_path.empty()) bench::write_result(json_path, result);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tinybvh_rays: %s\n", e.what());
        return 1;
    }
}
