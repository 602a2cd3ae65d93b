#include "core/render/render_engine.h"

#include <cstdlib>
#include <thread>

#include "core/scene/scene_motion.h"
#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism {

std::string resolve_backend_name(const std::string& requested) {
    if (requested != "auto") return requested;
    for (const BackendFactory& factory : registered_backends())
        if (factory.name == "cuda" && factory.probe().available) return "cuda";
    return "cpu";
}

namespace {

BvhLayout parse_bvh_layout(const std::string& name, const std::string& where) {
    if (name == "stack") return BvhLayout::Stack;
    if (name == "escape") return BvhLayout::Escape;
    if (name == "wide") return BvhLayout::Wide;
    throw Error(where + "'" + name + "' is not a BVH layout (stack, escape, wide or auto)");
}

}  // namespace

BvhLayout resolve_bvh_layout(const std::string& requested, const std::string& backend) {
    if (requested != "auto") return parse_bvh_layout(requested, "");
    std::string variable = setting(Setting::BvhLayout).value_or("");
    if (!variable.empty() && variable != "auto") return parse_bvh_layout(variable, "PRISM_BVH_LAYOUT: ");
    std::string api = parse_backend_spec(resolve_backend_name(backend)).api;
    return api == "cpu" || api == "cpu-ref" ? BvhLayout::Wide : BvhLayout::Stack;
}

std::string bvh_layout_name(BvhLayout layout) {
    switch (layout) {
        case BvhLayout::Stack: return "stack";
        case BvhLayout::Escape: return "escape";
        case BvhLayout::Wide: return "wide";
    }
    return "?";
}

RenderEngine::RenderEngine(const std::string& backend_name, const DeviceScene& scene, const GlContextHandles* gl)
    : name_(resolve_backend_name(backend_name)), scene_(scene) {
    BackendSpec spec = parse_backend_spec(name_);
    // The GPU kernels are built without the wide traversal (kernels/traverse.h says why).
    if (scene.bvh_options.layout == BvhLayout::Wide && spec.api != "cpu" && spec.api != "cpu-ref")
        throw Error(name_ +
                    ": the wide BVH layout is traced by the cpu backends only; use --bvh-layout stack, "
                    "escape or auto");
    if (spec.api == "cpu-ref") {
        unsigned threads = 0;
        if (!spec.device_filter.empty()) threads = static_cast<unsigned>(std::stoul(spec.device_filter));
        reference_ = std::make_unique<ReferenceRenderer>(scene, threads);
    } else {
        backend_ = create_backend(name_, gl);
        renderer_ = std::make_unique<Renderer>(*backend_, scene);
    }
}

RenderEngine::~RenderEngine() = default;

KernelResources RenderEngine::kernel_resources() const {
    if (!backend_) return {"the reference renderer compiles no stage kernels", {}};
    // A report, not a result: a query the driver fails says so in place of the numbers, and the measurements it
    // accompanies stand.
    try {
        return backend_->kernel_resources();
    } catch (const Error& error) {
        return {std::string("not read: ") + error.what(), {}};
    }
}

BackendInfo RenderEngine::info() const {
    if (backend_) return backend_->info();
    BackendInfo info;
    info.name = "cpu-ref";
    info.device = "host CPU (" + std::to_string(std::thread::hardware_concurrency()) + " threads)";
    info.driver = "host";
    info.api_version = "C++20 (recursive reference)";
    return info;
}

GlInteropOffer RenderEngine::gl_interop() {
    if (backend_) return backend_->gl_interop();
    return {nullptr, "the frame is already in host memory"};
}

FrameResult RenderEngine::render(const Camera& camera, const RenderSettings& settings,
                                 const std::function<void(double)>& progress) {
    if (reference_) return reference_->render(camera, settings, progress);
    return renderer_->render(camera, settings, [&](uint32_t depth, uint32_t max_depth) {
        if (progress) progress(double(depth) / max_depth);
    });
}

std::vector<RayHit> RenderEngine::trace(std::span<const RayQuery> rays, bool any_hit, uint32_t launches) {
    if (reference_) return reference_->trace(rays, any_hit, launches);
    return renderer_->trace(rays, any_hit, launches);
}

const std::vector<double>& RenderEngine::last_launch_ms() const {
    return reference_ ? reference_->last_launch_ms() : renderer_->last_launch_ms();
}

double RenderEngine::last_trace_ms() const {
    double sum = 0.0;
    for (double ms : last_launch_ms()) sum += ms;
    return sum;
}

void RenderEngine::update_instances(DeviceScene& scene, const std::vector<glm::mat4>& transforms, bool rebuild) {
    update_instance_transforms(scene, transforms, rebuild);
    if (renderer_) renderer_->update_instances(scene);
}

void RenderEngine::move_to(const Scene& scene, DeviceScene& device, double seconds) {
    const std::vector<DeformedVertices> posed = deformed_meshes_at(scene.animation, seconds);
    for (size_t d = 0; d < posed.size(); ++d) {
        if (posed[d].positions.empty()) continue;  // not finite at this moment: the mesh keeps its pose
        const uint32_t mesh = scene.animation.deformations[d].mesh;
        update_mesh_vertices(device, mesh, scene.meshes.at(mesh), posed[d]);
        // (The reference renderer reads `device` in place.)
        for (const DeviceScene::DeformableMesh& deformable : device.deformable_meshes)
            if (renderer_ && deformable.mesh == mesh) renderer_->update_mesh(device, deformable);
    }
    update_instance_transforms(device, instance_transforms_at(scene, seconds), false);
    if (renderer_) renderer_->update_instances(device);
    if (scene.animation.plays() && !scene.animation.lights.empty()) {
        update_lights(device, lights_at(scene, seconds));
        if (renderer_) renderer_->update_lights(device);
    }
}

}  // namespace prism
