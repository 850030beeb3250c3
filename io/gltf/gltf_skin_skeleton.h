// A glTF file's node graph and the skeleton of one of its skins, as sweepd's glTF readers
// (io/gltf/gltf_load.h, io/gltf/gltf_clip_load.h) both build it, so a clip read from a model's file
// animates the very joints of the model read from it (internal to io/):
//   node_local_matrix(node)   the node's local matrix (its matrix, or T * R * S)
//   build_node_graph          each node's parent and world matrix; bad children, two parents and
//                             cycles are LoadErrors
//   position_count(mesh)      the mesh's vertices, as its primitives' POSITION accessors count them
//   choose_skinned_node       the node with both mesh and skin whose mesh has the most vertices
//                             (-1 when none): its skin is the character's; counts such nodes in
//                             the report
//   build_skeleton            the skin's joints as a parents-first deform::Skeleton (see
//                             io/gltf/gltf_load.h for names and folded non-joint ancestors);
//                             new_index[skin slot] and order[new joint] = skin slot
#pragma once

#include <tiny_gltf.h>

#include <glm/glm.hpp>
#include <vector>

#include "deform/model/skeleton.h"
#include "io/gltf/gltf_accessors.h"
#include "io/load_report.h"

namespace sweepd::io::gltf {

glm::dmat4 node_local_matrix(const tinygltf::Node& node);

struct NodeGraph {
  std::vector<int> parent;
  std::vector<glm::dmat4> world;
};
NodeGraph build_node_graph(const AccessorReader& reader, const tinygltf::Model& gltf);

std::size_t position_count(const AccessorReader& reader, const tinygltf::Mesh& mesh);

int choose_skinned_node(const AccessorReader& reader, const tinygltf::Model& gltf,
                        LoadReport& report);

struct SkinSkeleton {
  deform::Skeleton skeleton;
  std::vector<int> new_index;  // per skin slot
  std::vector<int> order;      // per new joint: its skin slot
};
SkinSkeleton build_skeleton(const AccessorReader& reader, const tinygltf::Model& gltf,
                            const tinygltf::Skin& skin, const NodeGraph& graph);

}  // namespace sweepd::io::gltf
