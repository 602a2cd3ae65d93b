// `prism info`: which backends and devices this machine runs (and why the others do not), and with --scene the
// scene's size and BVH statistics.
#include <cstdio>
#include <thread>

#include <nlohmann/json.hpp>

#include "apps/cli_conventions.h"
#include "apps/commands.h"
#include "apps/scene_options.h"
#include "bench/bench_json.h"
#include "core/render/backend.h"
#include "core/util/build_info.h"

namespace prism::app {
namespace {

struct InfoOptions {
    SceneOptions scene;
    bool scene_given = false;
    std::string json;  // "-": standard output
};

nlohmann::json backends_json() {
    nlohmann::json list = nlohmann::json::array();
    list.push_back({{"name", "cpu-ref"},
                    {"available", true},
                    {"detail", "recursive reference renderer (the oracle)"},
                    {"devices", {"host CPU (" + std::to_string(std::thread::hardware_concurrency()) + " threads)"}}});
    for (const BackendFactory& factory : registered_backends()) {
        BackendAvailability a = factory.probe();
        list.push_back({{"name", a.name}, {"available", a.available}, {"detail", a.detail}, {"devices", a.devices}});
    }
    for (const char* missing : {"cuda", "opencl", "vulkan"}) {
        bool present = false;
        for (const BackendFactory& factory : registered_backends()) present |= factory.name == missing;
        if (!present)
            list.push_back({{"name", missing},
                            {"available", false},
                            {"detail", "not compiled into this build (see the configure summary)"},
                            {"devices", nlohmann::json::array()}});
    }
    return list;
}

void run_info(const InfoOptions& options) {
    route_output(options.json);
    nlohmann::json info = {{"commit", build_commit()}, {"build_type", build_type()}, {"backends", backends_json()}};
    if (options.scene_given) {
        LoadedScene loaded = load_and_build(options.scene);
        const DeviceScene& d = loaded.device;
        size_t meshes_triangles = 0;
        for (const Mesh& mesh : loaded.scene.meshes) meshes_triangles += mesh.triangles.size();
        info["scene"] = {{"source", options.scene.scene},
                         {"triangles", loaded.scene.triangle_count()},
                         {"mesh_triangles", meshes_triangles},
                         {"traced_triangles", d.traced_triangles},
                         {"degenerate_triangles", d.degenerate_triangles},
                         {"meshes", loaded.scene.meshes.size()},
                         {"instances", loaded.scene.instances.size()},
                         {"materials", loaded.scene.materials.size()},
                         {"textures", loaded.scene.textures.size()},
                         {"lights", loaded.scene.lights.size()},
                         {"bvh_method", options.scene.bvh},
                         {"bvh_layout", loaded.layout},
                         {"bvh_leaf_size", options.scene.bvh_leaf_size},
                         {"bvh_node_cost", options.scene.bvh_node_cost},
                         {"bvh_nodes", d.bvh_options.layout == BvhLayout::Wide ? d.wide_nodes.size() : d.nodes.size()},
                         {"top_level_nodes", d.top_level_nodes},
                         {"sah_cost", d.sah_cost},
                         {"bvh_build_ms", d.bvh_build_ms},
                         {"closed_solid_instances", d.closed_solid_instances},
                         {"closed_solid_ms", d.closed_solid_ms},
                         {"load_ms", loaded.load_ms},
                         {"device_bytes", d.byte_size()},
                         {"warnings", loaded.scene.warnings}};
        if (const NodeAnimation& animation = loaded.scene.animation; animation.plays())
            info["scene"]["animation"] = {{"name", animation.name},
                                          {"seconds", animation.duration},
                                          {"channels", animation.channels.size() + animation.weight_channels.size()},
                                          {"moving_instances", animation.instances.size()},
                                          {"deformed_meshes", animation.deformations.size()}};
    }
    if (!options.json.empty()) {
        bench::write_result(options.json, info);
        return;
    }
    std::printf("Prism %s (%s)\nBackends:\n", build_commit(), build_type());
    for (const auto& b : info["backends"]) {
        std::printf("  %-8s %s: %s\n", b["name"].get<std::string>().c_str(),
                    b["available"].get<bool>() ? "available" : "unavailable", b["detail"].get<std::string>().c_str());
        for (const auto& device : b["devices"]) std::printf("           - %s\n", device.get<std::string>().c_str());
    }
    if (info.contains("scene")) {
        const auto& s = info["scene"];
        std::printf(
            "Scene %s:\n  triangles %zu (traced %zu, degenerate %zu), meshes %zu, instances %zu, materials %zu, "
            "textures %zu, lights %zu\n  BVH (%s, %s layout): %zu nodes (%zu top level), SAH cost %.2f, "
            "built in %.1f ms; closed solids %zu (%.1f ms); load %.1f ms; %.1f MiB on the device\n",
            options.scene.scene.c_str(), s["triangles"].get<size_t>(), s["traced_triangles"].get<size_t>(),
            s["degenerate_triangles"].get<size_t>(), s["meshes"].get<size_t>(), s["instances"].get<size_t>(),
            s["materials"].get<size_t>(), s["textures"].get<size_t>(), s["lights"].get<size_t>(),
            options.scene.bvh.c_str(), s["bvh_layout"].get<std::string>().c_str(), s["bvh_nodes"].get<size_t>(),
            s["top_level_nodes"].get<size_t>(), s["sah_cost"].get<double>(), s["bvh_build_ms"].get<double>(),
            s["closed_solid_instances"].get<size_t>(), s["closed_solid_ms"].get<double>(), s["load_ms"].get<double>(),
            double(s["device_bytes"].get<size_t>()) / (1024.0 * 1024.0));
        if (s.contains("animation")) {
            const auto& a = s["animation"];
            const size_t channels = a["channels"].get<size_t>(), moving = a["moving_instances"].get<size_t>();
            const size_t deformed = a["deformed_meshes"].get<size_t>();
            std::printf(
                "  animation '%s': %.2f s, %zu channel%s moving %zu instance%s and deforming %zu mesh%s (played by "
                "--frames and the viewer's M)\n",
                a["name"].get<std::string>().c_str(), a["seconds"].get<double>(), channels, channels == 1 ? "" : "s",
                moving, moving == 1 ? "" : "s", deformed, deformed == 1 ? "" : "es");
        }
        for (const auto& w : s["warnings"]) std::printf("  warning: %s\n", w.get<std::string>().c_str());
    }
}

}  // namespace

void add_info_command(CLI::App& app) {
    auto options = std::make_shared<InfoOptions>();
    auto* command = app.add_subcommand("info", "Backends and devices found; with --scene, the scene and its BVH");
    add_scene_options(command, options->scene);
    // A bare --json (the older spelling) means standard output too.
    add_json_option(command, options->json, "write the report as JSON to a file")->expected(0, 1)->default_str("-");
    command->callback([options, command] {
        options->scene_given = command->count("--scene") > 0;
        run_info(*options);
    });
}

}  // namespace prism::app
