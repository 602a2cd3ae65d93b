#include "apps/worker_plan.h"

#include <algorithm>

#include "core/render/backend.h"
#include "core/util/error.h"
#include "core/render/render_engine.h"

namespace prism::app {
namespace {

size_t device_count(const std::string& api) {
    for (const BackendFactory& factory : registered_backends())
        if (factory.name == api) {
            BackendAvailability availability = factory.probe();
            if (!availability.available)
                throw Error(api + ":all: " + api + " is unavailable (" + availability.detail + ")");
            return std::max<size_t>(availability.devices.size(), 1);
        }
    throw Error("--backend " + api + ":all: no backend named '" + api + "' in this build");
}

bool is_cpu_api(const std::string& name) {
    std::string api = parse_backend_spec(resolve_backend_name(name)).api;
    return api == "cpu" || api == "cpu-ref";
}

}  // namespace

std::vector<std::string> split_backend_list(const std::string& text) {
    std::vector<std::string> names;
    size_t start = 0;
    while (true) {
        size_t comma = text.find(',', start);
        std::string name = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (name.empty()) throw Error("--backend '" + text + "': an empty entry in the list");
        names.push_back(name);
        if (comma == std::string::npos) return names;
        start = comma + 1;
    }
}

bool names_several_devices(const std::string& backend) {
    if (backend.find(',') != std::string::npos) return true;
    return parse_backend_spec(backend).device_filter == "all";
}

std::vector<std::string> plan_local_workers(const std::string& backend, int rank, int ranks, int local_rank) {
    std::vector<std::string> list = split_backend_list(backend);
    std::vector<std::string> mine;
    if (ranks > 1)
        mine.push_back(list[size_t(rank) % list.size()]);
    else
        mine = list;
    std::vector<std::string> workers;
    for (const std::string& entry : mine) {
        std::string name = resolve_backend_name(entry);
        BackendSpec spec = parse_backend_spec(name);
        if (spec.device_filter == "all") {
            // cpu and cpu-ref are one device (the host's threads); the GPU APIs number theirs.
            if (spec.api == "cpu" || spec.api == "cpu-ref") {
                workers.push_back(spec.api);
                continue;
            }
            for (size_t d = 0, n = device_count(spec.api); d < n; ++d)
                workers.push_back(spec.api + ":" + std::to_string(d));
        } else if (ranks > 1 && spec.api == "cuda" && spec.device_filter.empty()) {
            workers.push_back("cuda:" + std::to_string(size_t(local_rank) % device_count("cuda")));
        } else {
            workers.push_back(name);
        }
    }
    return workers;
}

BvhLayout shared_bvh_layout(const std::string& requested, const std::string& backend) {
    for (const std::string& entry : split_backend_list(backend))
        if (!is_cpu_api(entry)) return resolve_bvh_layout(requested, entry);
    return resolve_bvh_layout(requested, "cpu");
}

}  // namespace prism::app
