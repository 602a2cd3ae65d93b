// EXT_mesh_gpu_instancing: a node that draws its mesh many times, each with its own translation, rotation and
// scale read from accessors. Prism makes each of them an Instance of the one converted mesh (the two-level BVH's
// top level), so no triangle is copied.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace tinygltf {
class Model;
class Node;
}  // namespace tinygltf

namespace prism::gltf {

// The node-local transforms of the node's instances (T * R * S per instance, applied before the node's own
// world transform), or one identity when the node does not use the extension. Throws prism::Error naming the
// file for malformed attributes (wrong type, counts that differ).
std::vector<glm::mat4> gpu_instance_transforms(const tinygltf::Model& model, const tinygltf::Node& node,
                                               const std::string& file);

}  // namespace prism::gltf
