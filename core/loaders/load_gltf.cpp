#include "core/loaders/load_gltf.h"

#include <algorithm>
#include <string_view>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <sstream>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "core/util/error.h"
#include "core/loaders/glb_container.h"
#include "core/loaders/gltf_accessor.h"
#include "core/loaders/gltf_animation.h"
#include "core/loaders/gltf_instancing.h"
#include "core/loaders/gltf_material.h"
#include "core/loaders/gltf_compression_json.h"
#include "core/loaders/gltf_draco.h"
#include "core/loaders/gltf_meshopt.h"
#include "core/loaders/gltf_morph.h"
#include "core/loaders/gltf_rest_pose.h"
#include "core/loaders/gltf_skin.h"
#include "core/util/input_file.h"
#include "core/util/json_depth.h"
#include "core/util/load_progress.h"
#include "core/scene/mesh_tangents.h"
#include "core/scene/scene_motion.h"
#include "core/util/scene_read_rules.h"

namespace prism {
namespace {

// Prism decodes images itself (load_texture_from_memory) so that image errors carry Prism's messages and only
// the images a material uses are decoded; tinygltf just hands over the encoded bytes. For an image stored in a
// bufferView, tinygltf 2.7 passes &buffer[byteOffset] and byteLength without checking that the view lies inside
// its buffer (fuzz_glb: this copy read past the buffer, ASan heap-buffer-overflow), so the view is checked here
// against the model being loaded (`model`: its buffers and bufferViews are parsed before its images).
bool keep_encoded_image(tinygltf::Image* image, const int index, std::string* error, std::string*, int, int,
                        const unsigned char* bytes, int size, void* model) {
    const auto& loading = *static_cast<const tinygltf::Model*>(model);
    auto refuse = [&](const std::string& cause) {
        if (error) *error += "image " + std::to_string(index) + ": " + cause + "\n";
        return false;
    };
    if (size < 0) return refuse("byteLength out of range");
    if (image->bufferView >= 0) {  // tinygltf has checked that the view and its buffer exist
        const tinygltf::BufferView& view = loading.bufferViews.at(static_cast<size_t>(image->bufferView));
        const size_t available = loading.buffers.at(static_cast<size_t>(view.buffer)).data.size();
        if (view.byteOffset > available || view.byteLength > available - view.byteOffset)
            return refuse("bufferView " + std::to_string(image->bufferView) + " (offset " +
                          std::to_string(view.byteOffset) + ", " + std::to_string(view.byteLength) +
                          " bytes) lies outside its buffer (" + std::to_string(available) + " bytes)");
    }
    image->image.assign(bytes, bytes + size);
    return true;
}

// Buffers and images a glTF names by URI, read through tinygltf's file callbacks: only regular files in or below
// the scene's folder (core/util/scene_read_rules.h), read without blocking. The first refusal is kept and becomes the
// error, in Prism's words, instead of tinygltf's "File not found".
struct ExternalFiles {
    std::string file;  // the glTF, for messages
    std::string base;  // its folder, absolute; tinygltf joins every URI onto it
    std::optional<Error> refusal;

    // The URI as the file wrote it (percent-decoded by tinygltf), or nullopt for tinygltf's second guess, the
    // URI relative to the working directory, which Prism never reads.
    std::optional<std::string> uri_of(const std::string& joined) const {
        if (joined.size() <= base.size() || joined.compare(0, base.size(), base) != 0 || joined[base.size()] != '/')
            return std::nullopt;
        return joined.substr(base.size() + 1);
    }

    // Keeps the first refusal, as a message that starts with the glTF's name (a referenced file's own errors
    // start with that file's path).
    void refuse(const Error& error) {
        if (refusal) return;
        const std::string message = error.what();
        refusal = message.rfind(file + ": ", 0) == 0 ? error : file_error(file, message);
    }

    bool allowed(const std::string& joined) {
        if (refusal) return false;
        const std::optional<std::string> uri = uri_of(joined);
        if (!uri) return false;
        try {
            // tinygltf asks for the folder itself when a .gltf's buffer has no uri (only a .glb's own may not).
            if (uri->empty()) throw file_error(file, "a buffer or image without a uri (only a .glb's own buffer may)");
            // A percent-decoded %00 would end the path early, at another file or a folder.
            if (uri->find('\0') != std::string::npos) throw file_error(file, "a uri holds a NUL character (%00)");
            // An absolute URI means itself, not the folder + it that tinygltf joins.
            const bool absolute = !uri->empty() && uri->front() == '/';
            check_scene_reference(file, *uri, absolute ? std::filesystem::path(*uri) : std::filesystem::path(joined));
            std::error_code error;
            if (!std::filesystem::exists(joined, error)) return false;  // tinygltf: "File not found : <uri>"
            require_regular_file(joined);
        } catch (const Error& error) {
            refuse(error);
            return false;
        }
        return true;
    }
};

bool external_file_exists(const std::string& path, void* context) {
    return static_cast<ExternalFiles*>(context)->allowed(path);
}

std::string external_file_path(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool read_external_file(std::vector<unsigned char>* out, std::string* error, const std::string& path, void* context) {
    auto& files = *static_cast<ExternalFiles*>(context);
    if (!files.allowed(path)) {
        if (error) *error = "refused";
        return false;
    }
    try {
        const std::string bytes = read_input_file(path);
        out->assign(bytes.begin(), bytes.end());
    } catch (const Error& refused) {
        files.refuse(refused);
        if (error) *error = "refused";
        return false;
    }
    return true;
}

bool write_nothing(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
    if (error) *error = "Prism never writes glTF files";
    return false;
}

// The JSON text of a .gltf, or of a .glb's first chunk.
std::string_view json_text(std::string_view bytes, bool binary) { return binary ? glb_first_chunk(bytes) : bytes; }

// `bytes` (a .gltf, or a .glb when `binary`) with its JSON changed by `edit`, which says whether it changed anything;
// nullopt when nothing changed, the JSON does not parse or the container is broken (tinygltf then reports).
std::optional<std::string> with_json_edited(std::string_view bytes, bool binary,
                                            const std::function<bool(nlohmann::json&)>& edit) {
    std::optional<GlbParts> glb;
    if (binary && !(glb = split_glb(bytes))) return std::nullopt;
    nlohmann::json document = nlohmann::json::parse(binary ? glb->json : bytes, nullptr, false);
    if (document.is_discarded() || !document.is_object() || !edit(document)) return std::nullopt;
    std::string json = document.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (!binary) return json;
    return join_glb(glb->header, json, glb->rest);
}

// Deeper JSON than this is refused before tinygltf, which recurses once per level; real files nest about 8 deep.
constexpr size_t kMaxJsonDepth = 64;
constexpr size_t kBytesWorthReporting = size_t(8) << 20;  // glTF files that report their load's progress

glm::mat4 local_transform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        glm::mat4 matrix;
        for (int i = 0; i < 16; ++i) glm::value_ptr(matrix)[i] = static_cast<float>(node.matrix[i]);  // column-major
        return matrix;
    }
    glm::mat4 matrix(1.0f);
    if (node.translation.size() == 3)
        matrix = glm::translate(matrix, glm::vec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
        glm::quat rotation(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                           static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2]));  // w, x, y, z
        matrix *= glm::mat4_cast(glm::normalize(rotation));
    }
    if (node.scale.size() == 3) matrix = glm::scale(matrix, glm::vec3(node.scale[0], node.scale[1], node.scale[2]));
    return matrix;
}

class GltfImporter {
public:
    GltfImporter(const tinygltf::Model& model, std::string file, Scene& scene, std::vector<gltf::Skin> skins,
                 gltf::FileAnimation animation, bool report_progress)
        : model_(model),
          file_(std::move(file)),
          scene_(scene),
          materials_(model, file_, scene),
          skins_(std::move(skins)),
          rig_(std::move(animation), model, file_),
          report_progress_(report_progress) {}

    void import() {
        std::vector<int> roots;
        int scene_index = model_.defaultScene >= 0 ? model_.defaultScene : (model_.scenes.empty() ? -1 : 0);
        if (scene_index >= static_cast<int>(model_.scenes.size()))
            throw file_error(file_, "scene " + std::to_string(scene_index) + " does not exist");
        if (scene_index >= 0) {
            roots = model_.scenes[scene_index].nodes;
        } else {
            // No scenes: every node that is nobody's child is a root.
            std::vector<bool> is_child(model_.nodes.size(), false);
            for (const tinygltf::Node& node : model_.nodes)
                for (int child : node.children)
                    if (child >= 0 && child < static_cast<int>(is_child.size())) is_child[child] = true;
            for (size_t i = 0; i < model_.nodes.size(); ++i)
                if (!is_child[i]) roots.push_back(static_cast<int>(i));
        }
        node_state_.assign(model_.nodes.size(), NodeState::Unseen);
        node_world_.assign(model_.nodes.size(), glm::mat4(1.0f));
        for (size_t i = 0; i < roots.size(); ++i) {
            visit_tree(roots[i]);
            if (report_progress_) report_load_progress(double(i + 1) / double(roots.size()));
        }
        // Skinned meshes last: their joints may be anywhere in the trees, so every node's place must be known.
        for (const PendingSkin& pending : pending_skins_) add_skinned_instances(pending);
        scene_.animation = rig_.finish(scene_.warnings);
    }

private:
    enum class NodeState : uint8_t { Unseen, OnPath, Done };
    struct PendingNode {
        int node;
        glm::mat4 world;
        size_t next_child;
        gltf::AnimationRig::Place place;  // where an animation finds the node
    };
    struct PendingSkin {
        int node;
        int mesh;
    };

    // Depth-first over the node tree with an explicit stack: a file's chain of 20,000 nodes must not become
    // 20,000 native stack frames. Nodes are handled in the same order as a recursive walk would.
    void visit_tree(int root) {
        std::vector<PendingNode> stack;
        enter(root, glm::mat4(1.0f), {}, stack);
        while (!stack.empty()) {
            PendingNode& top = stack.back();
            const std::vector<int>& children = model_.nodes[top.node].children;
            if (top.next_child < children.size()) {
                const int child = children[top.next_child++];
                const glm::mat4 parent = top.world;  // `top` dangles once enter() grows the stack
                enter(child, parent, top.place, stack);
                continue;
            }
            node_state_[top.node] = NodeState::Done;
            stack.pop_back();
        }
    }

    void enter(int node_index, const glm::mat4& parent, gltf::AnimationRig::Place parent_place,
               std::vector<PendingNode>& stack) {
        if (node_index < 0 || node_index >= static_cast<int>(model_.nodes.size()))
            throw file_error(file_, "node " + std::to_string(node_index) + " does not exist");
        // glTF nodes form disjoint trees; a node reached twice would be instanced once per path, and a few
        // nodes sharing children multiply into billions of paths.
        if (node_state_[node_index] == NodeState::OnPath)
            throw file_error(file_, "node " + std::to_string(node_index) + " is its own ancestor");
        if (node_state_[node_index] == NodeState::Done)
            throw file_error(file_, "node " + std::to_string(node_index) + " has more than one parent");
        node_state_[node_index] = NodeState::OnPath;
        const tinygltf::Node& node = model_.nodes[node_index];
        const glm::mat4 local = local_transform(node);
        glm::mat4 world = parent * local;
        node_world_[node_index] = world;
        const gltf::AnimationRig::Place place = rig_.enter(node_index, local, parent_place);

        if (node.mesh >= 0 && node.skin >= 0) {
            if (node.skin >= static_cast<int>(skins_.size()))
                throw file_error(file_, "node " + std::to_string(node_index) + ": skin " + std::to_string(node.skin) +
                                            " does not exist");
            if (node.mesh >= static_cast<int>(model_.meshes.size()))
                throw file_error(file_, "mesh " + std::to_string(node.mesh) + " does not exist");
            pending_skins_.push_back({node_index, node.mesh});
        } else if (node.mesh >= 0) {
            add_mesh_instances(node, node.mesh, world, place);
        }
        if (node.camera >= 0) add_camera(node.camera, world, place);
        auto light = node.extensions.find("KHR_lights_punctual");
        if (light != node.extensions.end() && light->second.Has("light"))
            add_light(light->second.Get("light").GetNumberAsInt(), world, place);
        stack.push_back({node_index, world, 0, place});
    }

    // One Instance per primitive, times EXT_mesh_gpu_instancing's instances when the node has them.
    // `place`: where an animation finds the node (a skinned mesh's fallback passes none: it does not move).
    void add_mesh_instances(const tinygltf::Node& node, int mesh_index, const glm::mat4& node_world,
                            gltf::AnimationRig::Place place = {}) {
        if (mesh_index >= static_cast<int>(model_.meshes.size()))
            throw file_error(file_, "mesh " + std::to_string(mesh_index) + " does not exist");
        for (const glm::mat4& local : gltf::gpu_instance_transforms(model_, node, file_)) {
            const size_t first = scene_.instances.size();
            add_primitive_instances(node, mesh_index, node_world * local);
            for (size_t i = first; i < scene_.instances.size(); ++i) rig_.add_instance(uint32_t(i), place, local);
        }
    }

    // The morph weights a node draws its mesh with — its own "weights", else the mesh's defaults (animations do not
    // key weights) — and whose they are: -1 the mesh's (one copy for every node), else the node's index (its own).
    struct MorphWeights {
        std::span<const double> weights;
        int owner = -1;
    };
    MorphWeights morph_weights(const tinygltf::Node& node, const tinygltf::Mesh& mesh) const {
        const int node_index = static_cast<int>(&node - model_.nodes.data());
        const std::span<const double> weights = node.weights.empty() ? mesh.weights : node.weights;
        if (rig_.weights_keyed(node_index)) return {weights, node_index};  // posed anew at every moment: its own copy
        if (node.weights.empty() || node.weights == mesh.weights) return {mesh.weights, -1};
        return {node.weights, node_index};
    }

    void add_primitive_instances(const tinygltf::Node& node, int mesh_index, const glm::mat4& world) {
        for (size_t p = 0; p < model_.meshes[mesh_index].primitives.size(); ++p)
            add_primitive_instance(node, mesh_index, static_cast<int>(p), world);
    }

    void add_primitive_instance(const tinygltf::Node& node, int mesh_index, int p, const glm::mat4& world) {
        // A mirroring transform reverses the winding after transformation; a mirrored copy with reversed winding
        // keeps geometric normals facing the way the file meant.
        bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
        const tinygltf::Mesh& mesh = model_.meshes[mesh_index];
        const MorphWeights morph = morph_weights(node, mesh);
        auto key = std::make_tuple(mesh_index, p, mirrored, morph.owner);
        auto found = meshes_.find(key);
        uint32_t scene_mesh;
        if (found != meshes_.end()) {
            scene_mesh = found->second;
        } else {
            Mesh converted;
            std::optional<MeshDeformation> deformation;
            const int node_index = static_cast<int>(&node - model_.nodes.data());
            const bool keyed = rig_.weights_keyed(node_index) && !mesh.primitives[p].targets.empty();
            if (!convert_primitive(mesh, mesh_index, p, mirrored, keyed ? std::span<const double>() : morph.weights,
                                   converted)) {
                meshes_[key] = kSkipped;
                return;
            }
            if (morph.owner >= 0) count_copied_vertices(converted.positions.size());
            if (keyed) deformation = deform(mesh, mesh_index, p, morph.weights, converted, nullptr, nullptr);
            scene_.meshes.push_back(std::move(converted));
            scene_mesh = static_cast<uint32_t>(scene_.meshes.size() - 1);
            meshes_[key] = scene_mesh;
            if (deformation) {
                deformation->mesh = scene_mesh;
                rig_.add_deformation(std::move(*deformation), node_index, {});
            }
        }
        if (scene_mesh == kSkipped) return;
        add_instance(node, mesh, scene_mesh, world);
    }

    void add_instance(const tinygltf::Node& node, const tinygltf::Mesh& mesh, uint32_t scene_mesh,
                      const glm::mat4& world) {
        Instance instance;
        instance.mesh = scene_mesh;
        instance.transform = world;
        instance.name = node.name.empty() ? mesh.name : node.name;
        scene_.instances.push_back(std::move(instance));
    }

    // A skinned node's primitives, moved by their joints into world space (core/loaders/gltf_skin.h): one copy per
    // (mesh, primitive, skin), shared by the nodes that pair them. A primitive without JOINTS_0 and WEIGHTS_0, or a
    // skin whose joints are not all in the scene, is drawn where its node puts it, with a warning.
    void add_skinned_instances(const PendingSkin& pending) {
        const tinygltf::Node& node = model_.nodes[pending.node];
        const tinygltf::Mesh& mesh = model_.meshes[pending.mesh];
        const gltf::Skin& skin = skins_[node.skin];
        const std::string skin_name = "skin " + std::to_string(node.skin);
        for (int joint : skin.joints) {
            if (joint >= static_cast<int>(model_.nodes.size()))
                throw file_error(file_, skin_name + ": joint " + std::to_string(joint) + " is not a node (" +
                                            std::to_string(model_.nodes.size()) + " nodes)");
            if (node_state_[joint] != NodeState::Done) {
                warn_once(warned_unplaced_joint_, skin_name + ": joint " + std::to_string(joint) +
                                                      " is not in the scene; its meshes are drawn unskinned");
                add_mesh_instances(node, pending.mesh, node_world_[pending.node]);
                return;
            }
        }
        auto matrices = joint_matrices_.find(node.skin);
        if (matrices == joint_matrices_.end())
            matrices = joint_matrices_.emplace(node.skin, gltf::joint_matrices(model_, skin, node_world_, file_)).first;
        const MorphWeights morph = morph_weights(node, mesh);
        // The animation moves the mesh when it moves a joint or keys the node's weights.
        const bool joints_move =
            std::any_of(skin.joints.begin(), skin.joints.end(), [&](int joint) { return rig_.moves(joint); });
        const bool weights_keyed = rig_.weights_keyed(pending.node);
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            auto key = std::make_tuple(pending.mesh, static_cast<int>(p), node.skin, morph.owner);
            auto found = skinned_meshes_.find(key);
            if (found == skinned_meshes_.end()) {
                const bool moves = joints_move || (weights_keyed && !mesh.primitives[p].targets.empty());
                std::optional<uint32_t> skinned =
                    skinned_primitive(mesh, pending.mesh, static_cast<int>(p), morph.weights, matrices->second,
                                      moves ? &skin : nullptr, pending.node);
                if (!skinned) {
                    add_primitive_instance(node, pending.mesh, static_cast<int>(p), node_world_[pending.node]);
                    continue;
                }
                found = skinned_meshes_.emplace(key, *skinned).first;
            }
            if (found->second != kSkipped) add_instance(node, mesh, found->second, glm::mat4(1.0f));
        }
    }

    // The primitive skinned into world space as a new scene mesh (kSkipped when it is not traced), or nullopt
    // when it has no joints and weights to skin it by.
    // `moving`: the skin, when the animation moves the mesh (its joints, or the weights of node `node_index`).
    std::optional<uint32_t> skinned_primitive(const tinygltf::Mesh& mesh, int mesh_index, int p,
                                              std::span<const double> morph_weights,
                                              const std::vector<glm::mat4>& joints, const gltf::Skin* moving,
                                              int node_index) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        const std::string what = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
        std::vector<gltf::Influences> influences;
        for (int set = 0;; ++set) {
            auto joint_set = primitive.attributes.find("JOINTS_" + std::to_string(set));
            auto weight_set = primitive.attributes.find("WEIGHTS_" + std::to_string(set));
            if (joint_set == primitive.attributes.end() || weight_set == primitive.attributes.end()) break;
            // Sets may share one accessor, so a small file could name it a thousand times: what the sets copy
            // stays within the file's buffer size in floats (16M at least), charged before they are read.
            influence_floats_used_ += declared_floats(joint_set->second) + declared_floats(weight_set->second);
            if (influence_floats_used_ > file_float_budget())
                throw file_error(file_, what + ": its JOINTS_n and WEIGHTS_n sets would copy more than " +
                                            std::to_string(file_float_budget()) +
                                            " floats (the file's buffers' size in bytes, 16M at least)");
            gltf::Influences read{gltf::read_floats(model_, joint_set->second, file_),
                                  gltf::read_floats(model_, weight_set->second, file_)};
            if (read.joints.components != 4 || read.weights.components != 4)
                throw file_error(file_, what + ": JOINTS_" + std::to_string(set) + " and WEIGHTS_" +
                                            std::to_string(set) + " must be VEC4");
            influences.push_back(std::move(read));
        }
        if (influences.empty()) {
            warn_once(warned_unskinnable_, what +
                                               " belongs to a skinned node but has no JOINTS_0 and WEIGHTS_0; "
                                               "drawn unskinned");
            return std::nullopt;
        }
        Mesh converted;
        // A mirroring skin: convert_primitive reverses the winding and bitangent sign, as for a mirroring node.
        // (A deformed mesh keeps the winding its skin gives at load.)
        const bool mirrored = glm::determinant(glm::mat3(joints.front())) < 0.0f;
        const bool keyed_weights = moving && rig_.weights_keyed(node_index);
        if (!convert_primitive(mesh, mesh_index, p, mirrored, moving ? std::span<const double>() : morph_weights,
                               converted))
            return kSkipped;
        for (const gltf::Influences& set : influences)
            if (set.joints.count != converted.positions.size() || set.weights.count != converted.positions.size())
                throw file_error(file_, what + ": JOINTS and WEIGHTS counts differ from POSITION count");
        count_copied_vertices(converted.positions.size());
        SkinInfluences bound =
            gltf::skin_influences(influences, converted.positions.size(), joints.size(), what, file_);
        std::optional<MeshDeformation> deformation;
        if (moving) deformation = deform(mesh, mesh_index, p, morph_weights, converted, &bound, moving);
        DeformedVertices vertices = gltf::take_deformed(converted);
        skin_vertices(vertices, bound, joints);
        gltf::put_deformed(converted, std::move(vertices));
        scene_.meshes.push_back(std::move(converted));
        const auto scene_mesh = static_cast<uint32_t>(scene_.meshes.size() - 1);
        if (deformation) {
            deformation->mesh = scene_mesh;
            rig_.add_deformation(std::move(*deformation), keyed_weights ? node_index : -1, moving->joints);
        }
        return scene_mesh;
    }

    // `mesh`'s primitive p, converted without morph weights into `converted`, kept as a deformation's rest pose with
    // its targets (and `influences` and `skin`, when skinned); `converted` is then morphed by `weights`, the pose a
    // still frame shows. Nothing is kept (nullopt, `converted` morphed all the same) when the targets and the rest
    // pose would copy more than the file's animations may (its buffers' size in floats, 16M at least), with a warning.
    std::optional<MeshDeformation> deform(const tinygltf::Mesh& mesh, int mesh_index, int p,
                                          std::span<const double> weights, Mesh& converted, SkinInfluences* influences,
                                          const gltf::Skin* skin) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        const std::string what = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
        const std::vector<float> floats = gltf::morph_weights(primitive, weights, what, file_);
        const size_t vertices = converted.positions.size();
        // The rest pose's attributes, each target's and the influences', in floats (counted in double: a file may
        // declare more targets times vertices than size_t holds).
        const double needed =
            double(vertices) * (3 + (converted.normals.empty() ? 0 : 3) + (converted.tangents.empty() ? 0 : 4) +
                                9.0 * double(primitive.targets.size())) +
            (influences ? 2.0 * double(influences->weights.size()) : 0.0);
        std::optional<MeshDeformation> deformation;
        if (needed <= double(deformation_floats_left())) {
            deformation_floats_used_ += size_t(needed);
            deformation.emplace();
            deformation->targets = gltf::read_morph_targets(model_, primitive, converted, what, file_);
            deformation->weights = floats;
            deformation->rest = {converted.positions, converted.normals, converted.tangents};
            if (influences) deformation->influences = *influences;
            if (skin) deformation->inverse_bind = gltf::inverse_bind_matrices(model_, *skin, file_);
        } else {
            warn_once(warned_large_deformation_, what + ": its morph targets and skin are too large to animate (" +
                                                     std::to_string(uint64_t(std::min(needed, 1e19))) +
                                                     " floats); drawn as the file poses it");
            gltf::apply_morph_targets(model_, primitive, weights, converted, what, file_);  // a target at a time
            return deformation;
        }
        DeformedVertices posed = gltf::take_deformed(converted);
        morph_vertices(posed, deformation->targets, floats);
        gltf::put_deformed(converted, std::move(posed));
        return deformation;
    }

    // What copies of a file's data may take in all, in floats: its buffers' size in bytes, 16M at least.
    size_t file_float_budget() const {
        size_t buffer_bytes = 0;
        for (const tinygltf::Buffer& buffer : model_.buffers) buffer_bytes += buffer.data.size();
        return std::max(size_t(16) << 20, buffer_bytes);
    }

    size_t deformation_floats_left() const {
        const size_t budget = file_float_budget();
        return budget > deformation_floats_used_ ? budget - deformation_floats_used_ : 0;
    }

    // The floats an accessor holds as its header declares them (0 for one that does not exist: reading it fails).
    size_t declared_floats(int accessor) const {
        if (accessor < 0 || size_t(accessor) >= model_.accessors.size()) return 0;
        const tinygltf::Accessor& a = model_.accessors[size_t(accessor)];
        return a.count * size_t(std::max(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type)), 1));
    }

    // Each skinned copy, and each copy morphed with a node's own weights, is new memory: bounded, so a file cannot
    // pair one large mesh with a thousand skins or weight sets. The budget: four times the vertices of the file's
    // own primitives, and at least 8M.
    void count_copied_vertices(size_t vertices) {
        copied_vertices_ += vertices;
        if (copied_vertices_ > copied_vertex_budget())
            throw file_error(file_, "its skins and morph weights would copy more than " +
                                        std::to_string(copied_vertex_budget()) + " vertices");
    }

    size_t copied_vertex_budget() const {
        size_t vertices = 0;
        for (const tinygltf::Mesh& mesh : model_.meshes)
            for (const tinygltf::Primitive& primitive : mesh.primitives)
                if (auto position = primitive.attributes.find("POSITION"); position != primitive.attributes.end())
                    if (position->second >= 0 && position->second < static_cast<int>(model_.accessors.size()))
                        vertices += model_.accessors[position->second].count;
        return std::max<size_t>(size_t(8) << 20, 4 * vertices);
    }

    void warn_once(bool& warned, const std::string& message) {
        if (warned) return;
        scene_.warnings.push_back(file_ + ": " + message);
        warned = true;
    }

    bool convert_primitive(const tinygltf::Mesh& mesh, int mesh_index, int primitive_index, bool mirrored,
                           std::span<const double> morph_weights, Mesh& out) {
        const tinygltf::Primitive& primitive = mesh.primitives[primitive_index];
        std::string what = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(primitive_index);
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            if (!warned_non_triangles_)
                scene_.warnings.push_back(file_ + ": points and lines primitives are not traced; skipped");
            warned_non_triangles_ = true;
            return false;
        }
        auto attribute = [&](const char* name) {
            auto it = primitive.attributes.find(name);
            return it == primitive.attributes.end() ? -1 : it->second;
        };
        int position_accessor = attribute("POSITION");
        if (position_accessor < 0) {
            scene_.warnings.push_back(file_ + ": " + what + " has no POSITION; skipped");
            return false;
        }
        gltf::FloatArray positions = gltf::read_floats(model_, position_accessor, file_);
        if (positions.components != 3) throw file_error(file_, what + ": POSITION must be VEC3");
        size_t vertex_count = positions.count;
        out.name = mesh.name.empty() ? what : mesh.name;
        out.positions.resize(vertex_count);
        for (size_t i = 0; i < vertex_count; ++i)
            out.positions[i] = {positions.at(i, 0), positions.at(i, 1), positions.at(i, 2)};

        auto read_attribute = [&](const char* name, int min_components, int max_components) {
            gltf::FloatArray array;
            int accessor = attribute(name);
            if (accessor < 0) return array;
            array = gltf::read_floats(model_, accessor, file_);
            if (array.components < min_components || array.components > max_components)
                throw file_error(file_, what + ": " + name + " has the wrong number of components");
            if (array.count != vertex_count)
                throw file_error(file_, what + ": " + name + " count differs from POSITION count");
            return array;
        };
        if (gltf::FloatArray normals = read_attribute("NORMAL", 3, 3); normals.count) {
            out.normals.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i)
                out.normals[i] = {normals.at(i, 0), normals.at(i, 1), normals.at(i, 2)};
        }
        if (gltf::FloatArray uv = read_attribute("TEXCOORD_0", 2, 2); uv.count) {
            out.uv0.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i) out.uv0[i] = {uv.at(i, 0), uv.at(i, 1)};
        }
        if (gltf::FloatArray uv = read_attribute("TEXCOORD_1", 2, 2); uv.count) {
            out.uv1.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i) out.uv1[i] = {uv.at(i, 0), uv.at(i, 1)};
        }
        if (gltf::FloatArray colors = read_attribute("COLOR_0", 3, 4); colors.count) {
            out.colors.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i)
                out.colors[i] = {colors.at(i, 0), colors.at(i, 1), colors.at(i, 2),
                                 colors.components == 4 ? colors.at(i, 3) : 1.0f};
        }

        if (gltf::FloatArray tangents = read_attribute("TANGENT", 4, 4); tangents.count) {
            out.tangents.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i)
                out.tangents[i] = {tangents.at(i, 0), tangents.at(i, 1), tangents.at(i, 2), tangents.at(i, 3)};
        }

        // Morph targets before the tangents are generated (they follow the moved positions) and before any skin.
        if (gltf::morph_changes(primitive, morph_weights))
            gltf::apply_morph_targets(model_, primitive, morph_weights, out, what, file_);

        std::vector<uint32_t> indices;
        if (primitive.indices >= 0) {
            indices = gltf::read_indices(model_, primitive.indices, file_);
            for (uint32_t index : indices)
                if (index >= vertex_count)
                    throw file_error(file_, what + ": index " + std::to_string(index) + " out of range (" +
                                                std::to_string(vertex_count) + " vertices)");
        } else {
            indices.resize(vertex_count);
            for (size_t i = 0; i < vertex_count; ++i) indices[i] = static_cast<uint32_t>(i);
        }
        triangulate(primitive.mode, indices, out.triangles);
        if (mirrored)
            for (glm::uvec3& triangle : out.triangles) std::swap(triangle.y, triangle.z);
        uint32_t material = materials_.material(primitive.material);
        out.triangle_materials.assign(out.triangles.size(), material);
        const auto& normal_map = scene_.materials[material].normal_map;
        if (normal_map && out.tangents.empty()) generate_tangents(out, normal_map->uv_set);
        // The kernel's bitangent is cross(world normal, world tangent) * sign, and a mirroring transform turns
        // that cross product around: the mirrored copy carries the opposite sign.
        if (mirrored)
            for (glm::vec4& tangent : out.tangents) tangent.w = -tangent.w;
        return true;
    }

    // The glTF spec's vertex order for each mode, so front faces stay counter-clockwise.
    static void triangulate(int mode, const std::vector<uint32_t>& indices, std::vector<glm::uvec3>& triangles) {
        size_t n = indices.size();
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            triangles.reserve(n / 3);
            for (size_t i = 0; i + 2 < n; i += 3) triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
            return;
        }
        for (size_t i = 0; i + 2 < n; ++i) {
            glm::uvec3 triangle;
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
                triangle = (i % 2 == 0) ? glm::uvec3(indices[i], indices[i + 1], indices[i + 2])
                                        : glm::uvec3(indices[i + 1], indices[i], indices[i + 2]);
            else
                triangle = {indices[i + 1], indices[i + 2], indices[0]};
            // Strips stitch separate runs together with repeated indices; those zero-area joints are not geometry.
            if (triangle.x == triangle.y || triangle.y == triangle.z || triangle.x == triangle.z) continue;
            triangles.push_back(triangle);
        }
    }

    void add_camera(int camera_index, const glm::mat4& world, gltf::AnimationRig::Place place) {
        if (camera_index >= static_cast<int>(model_.cameras.size()))
            throw file_error(file_, "camera " + std::to_string(camera_index) + " does not exist");
        if (scene_.has_camera) return;  // the first camera instance wins
        const tinygltf::Camera& camera = model_.cameras[camera_index];
        if (camera.type != "perspective") {
            scene_.warnings.push_back(file_ + ": camera " + std::to_string(camera_index) +
                                      " is orthographic; Prism traces perspective cameras only, ignored");
            return;
        }
        // A node that gives no view (a zero scale, a non-finite transform) or a field of view that is not one leaves
        // the camera to the framing every file without a camera gets.
        const double yfov = camera.perspective.yfov;
        Camera placed = scene_.camera;
        if (!place_camera_at_node(placed, world) || !(yfov > 0.0 && yfov < 3.14159)) {
            scene_.warnings.push_back(file_error(file_, "camera " + std::to_string(camera_index) +
                                                            " gives no view (its node's transform or its yfov); the "
                                                            "scene is framed instead")
                                          .what());
            return;
        }
        scene_.camera = placed;
        scene_.camera.vertical_fov_degrees = glm::degrees(static_cast<float>(yfov));
        scene_.has_camera = true;
        rig_.set_camera(place);
    }

    void add_light(int light_index, const glm::mat4& world, gltf::AnimationRig::Place place) {
        if (light_index < 0 || light_index >= static_cast<int>(model_.lights.size()))
            throw file_error(file_, "light " + std::to_string(light_index) + " does not exist");
        const tinygltf::Light& source = model_.lights[light_index];
        Light light;
        if (source.color.size() >= 3)
            light.color = {static_cast<float>(source.color[0]), static_cast<float>(source.color[1]),
                           static_cast<float>(source.color[2])};
        light.intensity = static_cast<float>(source.intensity);
        // Directional and spot lights shine along the node's -z; point and spot lights sit at its origin.
        light.direction = glm::normalize(glm::vec3(world * glm::vec4(0, 0, -1, 0)));
        light.position = glm::vec3(world * glm::vec4(0, 0, 0, 1));
        if (source.type == "directional") {
            light.type = LightType::Directional;
        } else {
            light.type = source.type == "spot" ? LightType::Spot : LightType::Point;
            light.range = static_cast<float>(source.range);  // tinygltf: 0 when the file gives none
            light.inner_cone = static_cast<float>(source.spot.innerConeAngle);
            light.outer_cone = static_cast<float>(source.spot.outerConeAngle);
        }
        scene_.lights.push_back(light);
        rig_.add_light(static_cast<uint32_t>(scene_.lights.size() - 1), place);
    }

    static constexpr uint32_t kSkipped = ~0u;
    const tinygltf::Model& model_;
    std::string file_;
    Scene& scene_;
    gltf::MaterialConverter materials_;
    std::vector<gltf::Skin> skins_;
    gltf::AnimationRig rig_;
    bool report_progress_;
    // (mesh, primitive, mirrored, morph weights' owner) -> scene mesh
    std::map<std::tuple<int, int, bool, int>, uint32_t> meshes_;
    // (mesh, primitive, skin, morph weights' owner) -> scene mesh
    std::map<std::tuple<int, int, int, int>, uint32_t> skinned_meshes_;
    std::map<int, std::vector<glm::mat4>> joint_matrices_;  // per skin
    std::vector<NodeState> node_state_;                     // per node: unseen, on the current path, done
    std::vector<glm::mat4> node_world_;                     // per node reached: its world transform
    std::vector<PendingSkin> pending_skins_;
    size_t copied_vertices_ = 0;
    size_t deformation_floats_used_ = 0;  // what the deformed meshes' rest poses, targets and influences copy
    size_t influence_floats_used_ = 0;    // what the skinned primitives' JOINTS_n and WEIGHTS_n sets copy
    bool warned_large_deformation_ = false;
    bool warned_non_triangles_ = false;
    bool warned_unplaced_joint_ = false;
    bool warned_unskinnable_ = false;
};

bool has_extension(const std::filesystem::path& path, const char* extension) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == extension;
}

}  // namespace

void load_gltf(const std::filesystem::path& path, Scene& scene, const std::string& animation) {
    std::string file = path.string();
    const bool binary = has_extension(path, ".glb");
    std::string bytes = read_input_file(path);
    if (bytes.empty()) throw file_error(file, "empty file");
    if (bytes.size() > UINT32_MAX) throw file_error(file, "larger than 4 GiB, more than glTF allows");
    if (json_nesting_depth(json_text(bytes, binary)) > kMaxJsonDepth)
        throw file_error(file, "JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    // What tinygltf 2.7 would refuse is taken out of the JSON first, in one parse and one rewrite for every edit.
    nlohmann::json animations, skins;  // taken out for tinygltf, read by the importer
    if (const std::string_view json = json_text(bytes, binary);
        mentions_animation(json) || mentions_compression(json)) {
        try {
            if (std::optional<std::string> rewritten = with_json_edited(bytes, binary, [&](nlohmann::json& document) {
                    RestPoseEdit rest_pose = remove_animation(document);
                    animations = std::move(rest_pose.animations);
                    skins = std::move(rest_pose.skins);
                    const bool prepared = prepare_for_decompression(document);
                    return rest_pose.changed || prepared;
                }))
                bytes = std::move(*rewritten);
        } catch (const nlohmann::json::exception& exception) {  // the edits check each value's type; this is a net
            throw file_error(file, library_message(exception.what(), "malformed glTF"));
        }
    }
    // The GLB spec pads the JSON chunk to 4 bytes and tinygltf insists; some exporters (trimesh's, for one) did not
    // pad, and other viewers read those files. The chunk is padded here, with a warning.
    bool padded_json = false;
    if (std::optional<GlbParts> glb = binary ? split_glb(bytes) : std::nullopt; glb && glb->json.size() % 4 != 0) {
        if (std::optional<std::string> repacked = join_glb(glb->header, glb->json, glb->rest)) {
            bytes = std::move(*repacked);
            padded_json = true;
        }
    }

    if (binary)
        if (std::optional<std::string> overrun = glb_second_chunk_overrun(bytes)) throw file_error(file, *overrun);

    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    loader.SetImageLoader(keep_encoded_image, &model);
    std::error_code ignored;
    ExternalFiles files{file, std::filesystem::absolute(path, ignored).parent_path().string(), std::nullopt};
    loader.SetFsCallbacks({external_file_exists, external_file_path, read_external_file, write_nothing, &files});
    std::string error, warning;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, data, unsigned(bytes.size()), files.base)
                    : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), unsigned(bytes.size()),
                                                 files.base);
    } catch (const std::exception& exception) {  // tinygltf reports by return value, but its JSON layer may throw
        throw file_error(file, library_message(exception.what(), "malformed glTF"));
    }
    if (!ok || !error.empty() || files.refusal) {
        if (files.refusal) throw *files.refusal;
        throw file_error(file, library_message(error, "malformed glTF"));
    }
    std::istringstream lines(warning);
    for (std::string line; std::getline(lines, line);)
        if (!line.empty()) scene.warnings.push_back(file + ": " + library_message(line, line));

    if (padded_json) scene.warnings.push_back(file + ": the GLB's JSON chunk is not padded to 4 bytes; read anyway");
    // Required extensions Prism reads (or, for KHR_animation_pointer, whose channels are not played anyway,
    // need not): any other gives a warning and the file loads without it.
    static constexpr std::string_view kReadExtensions[] = {"KHR_texture_transform",
                                                           "KHR_materials_emissive_strength",
                                                           "KHR_lights_punctual",
                                                           "KHR_mesh_quantization",
                                                           "EXT_mesh_gpu_instancing",
                                                           "KHR_animation_pointer",
                                                           "KHR_draco_mesh_compression",
                                                           "EXT_meshopt_compression",
                                                           "KHR_meshopt_compression",
                                                           "EXT_texture_webp",
                                                           "KHR_materials_pbrSpecularGlossiness",
                                                           "KHR_materials_unlit",
                                                           "KHR_materials_iridescence",
                                                           "KHR_materials_clearcoat"};
    for (const std::string& required : model.extensionsRequired)
        if (std::find(std::begin(kReadExtensions), std::end(kReadExtensions), required) == std::end(kReadExtensions))
            scene.warnings.push_back(file + ": required extension " + required + " is not supported");

    // Compressed data become plain buffers first, so the importer reads every accessor one way.
    decode_meshopt_buffer_views(model, file);
    decode_draco_primitives(model, file);

    // Progress for large files only: a small one loads at once, and one that fails leaves only its error line.
    const bool report_progress = bytes.size() >= kBytesWorthReporting;
    if (report_progress) report_load_progress(0.3);  // parsed; the meshes and textures follow
    LoadProgressShare importing(0.3, 1.0);
    GltfImporter(model, file, scene, gltf::parse_skins(skins, file),
                 gltf::read_animations(animations, model, file, animation), report_progress)
        .import();
}

}  // namespace prism
