#include "io/gltf/gltf_skin_skeleton.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <set>
#include <string>

#include "io/rest_transform.h"

namespace sweepd::io::gltf {

namespace {

// Rest TRS straight from the node's own fields (exact when it has no matrix); false when a
// scale is zero (no bind matrix could be inverted).
bool node_trs(const tinygltf::Node& node, deform::Joint& joint) {
  if (node.matrix.size() == 16) return decompose_rest_transform(node_local_matrix(node), joint);
  if (node.translation.size() == 3)
    joint.rest_translation =
        glm::vec3(glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    joint.rest_rotation = glm::normalize(
        glm::quat(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                  static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2])));
  if (node.scale.size() == 3)
    joint.rest_scale = glm::vec3(glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return joint.rest_scale.x != 0.0f && joint.rest_scale.y != 0.0f && joint.rest_scale.z != 0.0f;
}

}  // namespace

glm::dmat4 node_local_matrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = node.matrix[i];
    return m;
  }
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m = glm::translate(m,
                       glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    m = m * glm::mat4_cast(glm::normalize(glm::dquat(node.rotation[3], node.rotation[0],
                                                     node.rotation[1], node.rotation[2])));
  if (node.scale.size() == 3)
    m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

NodeGraph build_node_graph(const AccessorReader& reader, const tinygltf::Model& gltf) {
  const int n = static_cast<int>(gltf.nodes.size());
  NodeGraph graph{std::vector<int>(n, -1), std::vector<glm::dmat4>(n)};
  for (int p = 0; p < n; ++p)
    for (int c : gltf.nodes[p].children) {
      if (c < 0 || c >= n || c == p)
        reader.fail("node " + std::to_string(p) + " has an invalid child " + std::to_string(c));
      if (graph.parent[c] >= 0)
        reader.fail("node " + std::to_string(c) + " has two parents (" +
                    std::to_string(graph.parent[c]) + " and " + std::to_string(p) + ")");
      graph.parent[c] = p;
    }
  std::vector<char> done(n, 0);
  for (int start = 0; start < n; ++start) {
    std::vector<int> chain;  // start and its ancestors that still need a world matrix
    for (int v = start; v >= 0 && !done[v]; v = graph.parent[v]) {
      chain.push_back(v);
      if (static_cast<int>(chain.size()) > n)
        reader.fail("the node hierarchy has a cycle through node " + std::to_string(start));
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const int v = *it, p = graph.parent[v];
      const glm::dmat4 local = node_local_matrix(gltf.nodes[v]);
      graph.world[v] = p >= 0 ? graph.world[p] * local : local;
      done[v] = 1;
    }
  }
  return graph;
}

std::size_t position_count(const AccessorReader& reader, const tinygltf::Mesh& mesh) {
  std::size_t count = 0;
  for (const tinygltf::Primitive& primitive : mesh.primitives)
    if (auto it = primitive.attributes.find("POSITION"); it != primitive.attributes.end())
      count += reader.accessor(it->second, "POSITION").count;
  return count;
}

int choose_skinned_node(const AccessorReader& reader, const tinygltf::Model& gltf,
                        LoadReport& report) {
  int best = -1;
  std::size_t best_count = 0;
  for (int i = 0; i < static_cast<int>(gltf.nodes.size()); ++i) {
    const tinygltf::Node& node = gltf.nodes[i];
    if (node.mesh < 0 || node.skin < 0) continue;
    if (node.mesh >= static_cast<int>(gltf.meshes.size()) ||
        node.skin >= static_cast<int>(gltf.skins.size()))
      reader.fail("node " + std::to_string(i) + " refers to a missing mesh or skin");
    ++report.skinned_mesh_count;
    const std::size_t count = position_count(reader, gltf.meshes[node.mesh]);
    if (best < 0 || count > best_count) best = i, best_count = count;
  }
  return best;
}

SkinSkeleton build_skeleton(const AccessorReader& reader, const tinygltf::Model& gltf,
                            const tinygltf::Skin& skin, const NodeGraph& graph) {
  const int count = static_cast<int>(skin.joints.size());
  if (count == 0) reader.fail("the skin has no joints");
  std::map<int, int> slot_of_node;
  for (int s = 0; s < count; ++s) {
    const int node = skin.joints[s];
    if (node < 0 || node >= static_cast<int>(gltf.nodes.size()))
      reader.fail("skin joint " + std::to_string(s) + " refers to missing node " +
                  std::to_string(node));
    if (!slot_of_node.emplace(node, s).second)
      reader.fail("node " + std::to_string(node) + " appears twice in the skin's joints");
  }
  // Parent slot: the nearest ancestor node that is a joint.
  std::vector<int> parent_slot(count, -1);
  for (int s = 0; s < count; ++s)
    for (int v = graph.parent[skin.joints[s]]; v >= 0; v = graph.parent[v])
      if (auto it = slot_of_node.find(v); it != slot_of_node.end()) {
        parent_slot[s] = it->second;
        break;
      }
  // Depth-first pre-order from the roots, children in skin order: parents come first.
  SkinSkeleton result;
  result.new_index.assign(count, -1);
  std::vector<int> stack;
  for (int s = count - 1; s >= 0; --s)
    if (parent_slot[s] < 0) stack.push_back(s);
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    result.new_index[s] = static_cast<int>(result.order.size());
    result.order.push_back(s);
    for (int c = count - 1; c >= 0; --c)
      if (parent_slot[c] == s) stack.push_back(c);
  }
  std::set<std::string> used_names;
  for (int s : result.order) {
    const int node_index = skin.joints[s];
    const tinygltf::Node& node = gltf.nodes[node_index];
    deform::Joint joint;
    const std::string base = node.name.empty() ? "joint_" + std::to_string(node_index) : node.name;
    joint.name = base;
    for (int k = 2; !used_names.insert(joint.name).second; ++k)
      joint.name = base + "_" + std::to_string(k);
    const int parent = parent_slot[s];
    joint.parent = parent < 0 ? -1 : result.new_index[parent];
    const int parent_node = graph.parent[node_index];
    const bool direct = parent < 0 ? parent_node < 0 : parent_node == skin.joints[parent];
    // Non-joint nodes in between (e.g. a Z-up to Y-up root matrix) are folded in.
    const bool ok = direct ? node_trs(node, joint)
                           : decompose_rest_transform(
                                 parent < 0 ? graph.world[node_index]
                                            : glm::inverse(graph.world[skin.joints[parent]]) *
                                                  graph.world[node_index],
                                 joint);
    if (!ok)
      reader.fail("joint node " + std::to_string(node_index) + " ('" + joint.name +
                  "') has a degenerate (zero-scale) rest transform");
    if (!finite_rest_transform(joint))
      reader.fail("joint node " + std::to_string(node_index) + " ('" + joint.name +
                  "') has a rest transform that is not finite (NaN or Inf)");
    result.skeleton.joints.push_back(joint);
  }
  return result;
}

}  // namespace sweepd::io::gltf
