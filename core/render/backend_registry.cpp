#include <algorithm>
#include <cctype>

#include "core/render/backend.h"
#include "core/util/error.h"

namespace prism {

const char* device_array_name(DeviceArray array) {
    switch (array) {
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    case DeviceArray::name:                           \
        return #name;
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
        default: return "?";
    }
}

size_t device_array_element_size(DeviceArray array) {
    switch (array) {
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    case DeviceArray::name:                           \
        return sizeof(type);
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
        default: return 0;
    }
}

DeviceArrayRole device_array_role(DeviceArray array) {
    static constexpr DeviceArrayRole roles[] = {
#define PRISM_ROLE_scene DeviceArrayRole::Scene
#define PRISM_ROLE_frame DeviceArrayRole::Frame
#define PRISM_ROLE_queue DeviceArrayRole::Queue
#define PRISM_ROLE_pixel DeviceArrayRole::Pixel
#define RT_DATA_ARRAY(slot, type, name, access, role) PRISM_ROLE_##role,
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    };
    return roles[static_cast<size_t>(array)];
}

namespace {

// kernels/stage_list.h's rows, indexed by Stage.
struct StageRow {
    const char* name;
    StagePass pass;
    StageLaunch launch;
    uint32_t needs;
};

constexpr StageRow kStages[] = {
#define RT_STAGE(name, Name, pass, launch, needs) {#name, StagePass::pass, StageLaunch::launch, needs},
#include "kernels/stage_list.h"
#undef RT_STAGE
};

const StageRow& stage_row(Stage stage) { return kStages[static_cast<size_t>(stage)]; }

}  // namespace

const char* stage_name(Stage stage) { return stage_row(stage).name; }

StagePass stage_pass(Stage stage) { return stage_row(stage).pass; }

uint32_t stage_needs(Stage stage) { return stage_row(stage).needs; }

StageLaunch stage_launch(Stage stage) { return stage_row(stage).launch; }

// kernels/stage_list.h's rule, checked: a GridSizesQueue stage writes the indirect launches' arguments, so no frame
// may skip it.
#define RT_STAGE(name, Name, pass, launch, needs)                                     \
    static_assert(StageLaunch::launch != StageLaunch::GridSizesQueue || (needs) == 0, \
                  "kernels/stage_list.h: stage '" #name "' sizes the queues and must run in every frame");
#include "kernels/stage_list.h"
#undef RT_STAGE

BackendSpec parse_backend_spec(const std::string& text) {
    BackendSpec spec;
    auto colon = text.find(':');
    spec.api = text.substr(0, colon);
    if (colon != std::string::npos) spec.device_filter = text.substr(colon + 1);
    std::transform(spec.api.begin(), spec.api.end(), spec.api.begin(), [](unsigned char c) { return std::tolower(c); });
    return spec;
}

static std::vector<BackendFactory>& registry() {
    static std::vector<BackendFactory> factories;
    return factories;
}

void register_backend(BackendFactory factory) {
    for (const BackendFactory& existing : registry())
        if (existing.name == factory.name) return;
    registry().push_back(std::move(factory));
}

const std::vector<BackendFactory>& registered_backends() { return registry(); }

std::unique_ptr<Backend> create_backend(const std::string& text, const GlContextHandles* gl) {
    BackendSpec spec = parse_backend_spec(text);
    std::string known = "cpu-ref";
    for (const BackendFactory& factory : registry()) {
        known += ", " + factory.name;
        if (factory.name == spec.api) return factory.create(spec.device_filter, gl);
    }
    throw Error("unknown backend '" + text + "' (this build has: " + known + "; `prism info` says which run here)");
}

}  // namespace prism
