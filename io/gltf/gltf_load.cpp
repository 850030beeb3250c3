#include "io/gltf/gltf_load.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <iterator>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "io/bind_pose_vertices.h"
#include "io/gltf/gltf_accessors.h"
#include "io/gltf/gltf_skin_skeleton.h"

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;
using namespace gltf;

// Per-vertex data of one primitive before skinning.
struct SourceVertices {
  std::vector<double> positions, normals, uvs;
  std::vector<std::vector<double>> joint_sets, weight_sets;  // JOINTS_n, WEIGHTS_n: 4 per vertex
};

// Skinning matrices world_rest * inverseBind per new joint index.
std::vector<glm::dmat4> skinning_matrices(const AccessorReader& reader, const tinygltf::Skin& skin,
                                          const SkinSkeleton& skeleton) {
  const int count = static_cast<int>(skin.joints.size());
  std::vector<glm::dmat4> inverse_bind(count, glm::dmat4(1.0));
  if (skin.inverseBindMatrices >= 0) {
    const std::vector<double> values = reader.read(
        skin.inverseBindMatrices, {"inverseBindMatrices", TINYGLTF_TYPE_MAT4, kFloat, false});
    if (values.size() < static_cast<std::size_t>(count) * 16)
      reader.fail("inverseBindMatrices has " + std::to_string(values.size() / 16) +
                  " matrices for " + std::to_string(count) + " joints");
    for (int s = 0; s < count; ++s)
      for (int i = 0; i < 16; ++i) inverse_bind[s][i / 4][i % 4] = values[s * 16 + i];
  }
  const std::vector<glm::mat4> world = skeleton.skeleton.world_rest_matrices();
  std::vector<glm::dmat4> result(count);
  for (int j = 0; j < count; ++j)
    result[j] = glm::dmat4(world[j]) * inverse_bind[skeleton.order[j]];
  return result;
}

// How one mesh node's vertices are bound: through the skin, or rigidly to one joint.
struct NodeBinding {
  int joint;                             // rigid: the joint; skinned: for vertices with no weight
  bool rigid;                            // no skin: weight 1 on `joint`
  std::span<const glm::dmat4> skinning;  // per joint; rigid: the node's world matrix at `joint`
};

class ModelAssembler {
 public:
  ModelAssembler(const AccessorReader& reader, const SkinSkeleton& skeleton, LoadReport& report)
      : reader_(reader), skeleton_(skeleton), vertices_(model_, report) {}

  // Appends the primitive's vertices and triangles as mesh part `part` (its range filled here).
  void add_primitive(const tinygltf::Primitive& primitive, const std::string& what,
                     const NodeBinding& binding, deform::MeshPart part) {
    part.first_vertex = static_cast<std::uint32_t>(model_.positions.size());
    part.first_index = static_cast<std::uint32_t>(model_.indices.size());
    part.rigid_joint = binding.rigid ? binding.joint : -1;
    const auto& attributes = primitive.attributes;
    auto attribute = [&](const std::string& name) {
      const auto it = attributes.find(name);
      return it == attributes.end() ? -1 : it->second;
    };
    const std::vector<const char*> required =
        binding.rigid ? std::vector<const char*>{"POSITION"}
                      : std::vector<const char*>{"POSITION", "JOINTS_0", "WEIGHTS_0"};
    for (const char* name : required)
      if (attribute(name) < 0) reader_.fail(what + " has no " + name + " attribute");
    SourceVertices source;
    source.positions = reader_.read(attribute("POSITION"),
                                    {"POSITION of " + what, TINYGLTF_TYPE_VEC3, kFloat, false});
    const std::size_t n = source.positions.size() / 3;
    auto read_per_vertex = [&](const std::string& name, const AccessorSpec& spec) {
      std::vector<double> values = reader_.read(attribute(name), spec);
      const std::size_t components = tinygltf::GetNumComponentsInType(spec.type);
      if (values.size() != n * components)
        reader_.fail(spec.what + " has " + std::to_string(values.size() / components) +
                     " elements for " + std::to_string(n) + " vertices");
      return values;
    };
    if (attribute("NORMAL") >= 0)
      source.normals =
          read_per_vertex("NORMAL", {"NORMAL of " + what, TINYGLTF_TYPE_VEC3, kFloat, false});
    if (attribute("TEXCOORD_0") >= 0)
      source.uvs = read_per_vertex(
          "TEXCOORD_0", {"TEXCOORD_0 of " + what, TINYGLTF_TYPE_VEC2, kFloatOrUnorm, true});
    for (int set = 0; !binding.rigid; ++set) {
      const std::string joints_name = "JOINTS_" + std::to_string(set);
      const std::string weights_name = "WEIGHTS_" + std::to_string(set);
      if (attribute(joints_name) < 0 && attribute(weights_name) < 0) break;
      if (attribute(joints_name) < 0 || attribute(weights_name) < 0)
        reader_.fail(what + " has only one of " + joints_name + " and " + weights_name);
      source.joint_sets.push_back(read_per_vertex(
          joints_name, {joints_name + " of " + what, TINYGLTF_TYPE_VEC4, kJointTypes, false}));
      source.weight_sets.push_back(read_per_vertex(
          weights_name, {weights_name + " of " + what, TINYGLTF_TYPE_VEC4, kFloatOrUnorm, true}));
    }
    const std::size_t base = model_.positions.size();
    append_indices(primitive, what, n, base);
    append_vertices(source, what, n, binding);
    part.vertex_count = static_cast<std::uint32_t>(model_.positions.size()) - part.first_vertex;
    part.index_count = static_cast<std::uint32_t>(model_.indices.size()) - part.first_index;
    model_.parts.push_back(std::move(part));
  }

  std::size_t part_count() const { return model_.parts.size(); }

  deform::Model finish() {
    if (model_.positions.empty()) reader_.fail("the skinned mesh has no vertices");
    vertices_.finish(skeleton_.skeleton, "NORMAL", "TEXCOORD_0");
    model_.skeleton = skeleton_.skeleton;
    return std::move(model_);
  }

 private:
  void append_indices(const tinygltf::Primitive& primitive, const std::string& what, std::size_t n,
                      std::size_t base) {
    if (primitive.indices < 0) {
      if (n % 3 != 0)
        reader_.fail(what + " is non-indexed with " + std::to_string(n) +
                     " vertices, not a multiple of 3 (triangles)");
      for (std::size_t v = 0; v < n; ++v)
        model_.indices.push_back(static_cast<std::uint32_t>(base + v));
      return;
    }
    const std::vector<double> indices = reader_.read(
        primitive.indices, {"indices of " + what, TINYGLTF_TYPE_SCALAR, kIndexTypes, false});
    if (indices.size() % 3 != 0)
      reader_.fail("indices of " + what + " has " + std::to_string(indices.size()) +
                   " entries, not a multiple of 3 (triangles)");
    for (std::size_t i = 0; i < indices.size(); ++i) {
      if (indices[i] >= static_cast<double>(n))
        reader_.fail("indices of " + what + " entry " + std::to_string(i) + " refers to vertex " +
                     std::to_string(static_cast<std::uint64_t>(indices[i])) + " of " +
                     std::to_string(n) + " (out of range)");
      model_.indices.push_back(static_cast<std::uint32_t>(base + indices[i]));
    }
  }

  // Fills influences_ with vertex v's non-zero (new joint index, weight) pairs over all
  // JOINTS_n/WEIGHTS_n sets, repeated joints merged.
  void gather_influences(const SourceVertices& source, const std::string& what, std::size_t v) {
    const std::size_t joint_count = skeleton_.new_index.size();
    influences_.clear();
    for (std::size_t set = 0; set < source.joint_sets.size(); ++set)
      for (int k = 0; k < 4; ++k) {
        const double slot = source.joint_sets[set][v * 4 + k];
        const double weight = source.weight_sets[set][v * 4 + k];
        const std::string name =
            "_" + std::to_string(set) + " of " + what + " vertex " + std::to_string(v);
        if (slot >= static_cast<double>(joint_count))
          reader_.fail("JOINTS" + name + " refers to joint " +
                       std::to_string(static_cast<long>(slot)) + " but the skin has " +
                       std::to_string(joint_count) + " (out of range)");
        if (weight < 0.0)
          reader_.fail("WEIGHTS" + name + " has a negative weight " + std::to_string(weight));
        if (weight == 0.0) continue;
        add_influence(influences_, skeleton_.new_index[static_cast<int>(slot)], weight);
      }
  }

  void append_vertices(const SourceVertices& source, const std::string& what, std::size_t n,
                       const NodeBinding& binding) {
    for (std::size_t v = 0; v < n; ++v) {
      gather_influences(source, what, v);
      if (binding.rigid) influences_.assign(1, {binding.joint, 1.0});
      const glm::dvec3 position(source.positions[v * 3], source.positions[v * 3 + 1],
                                source.positions[v * 3 + 2]);
      glm::dvec3 normal;
      if (!source.normals.empty())
        normal =
            glm::dvec3(source.normals[v * 3], source.normals[v * 3 + 1], source.normals[v * 3 + 2]);
      glm::vec2 uv;
      if (!source.uvs.empty()) uv = glm::vec2(source.uvs[v * 2], source.uvs[v * 2 + 1]);
      vertices_.append(influences_, binding.joint, binding.skinning, position,
                       source.normals.empty() ? nullptr : &normal,
                       source.uvs.empty() ? nullptr : &uv);
    }
  }

  const AccessorReader& reader_;
  const SkinSkeleton& skeleton_;
  deform::Model model_;
  BindPoseVertices vertices_;
  std::vector<std::pair<int, double>> influences_;  // scratch for one vertex
};

// Mesh node's nearest ancestor joint (new index), else -1.
int ancestor_joint(const NodeGraph& graph, const tinygltf::Skin& skin, const SkinSkeleton& skeleton,
                   int mesh_node) {
  for (int v = graph.parent[mesh_node]; v >= 0; v = graph.parent[v])
    for (std::size_t s = 0; s < skin.joints.size(); ++s)
      if (skin.joints[s] == v) return skeleton.new_index[s];
  return -1;
}

// The file's name for a mesh node: its mesh's, else the node's, else mesh_<index>.
std::string mesh_name(const tinygltf::Model& gltf, int node) {
  const int mesh = gltf.nodes[node].mesh;
  if (!gltf.meshes[mesh].name.empty()) return gltf.meshes[mesh].name;
  if (!gltf.nodes[node].name.empty()) return gltf.nodes[node].name;
  return "mesh_" + std::to_string(mesh);
}

// Loads one mesh node's triangle primitives; returns how many (0: none was triangles, and
// `last_mode` holds the last primitive's mode).
int add_mesh_node(ModelAssembler& assembler, const tinygltf::Model& gltf, int node,
                  const NodeBinding& binding, std::uint32_t ordinal, LoadReport& report,
                  int& last_mode) {
  const int mesh_index = gltf.nodes[node].mesh;
  const tinygltf::Mesh& mesh = gltf.meshes[mesh_index];
  const std::string mesh_what = "mesh " + std::to_string(mesh_index);
  int added = 0;
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = mesh.primitives[p];
    const std::string what = mesh_what + " primitive " + std::to_string(p);
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES) {
      last_mode = mode;
      report.warnings.push_back(what + " has mode " + std::to_string(mode) +
                                ", not triangles (4); skipped");
      continue;
    }
    deform::MeshPart part;
    part.name = mesh_name(gltf, node);
    part.mesh = ordinal;
    if (primitive.material >= 0 && primitive.material < static_cast<int>(gltf.materials.size()))
      part.material = gltf.materials[primitive.material].name;
    assembler.add_primitive(primitive, what, binding, std::move(part));
    ++added;
  }
  report.source_primitive_count += added;
  return added;
}

}  // namespace

deform::Model load_gltf(const fs::path& file, LoadReport* report) {
  return load_gltf(file, GltfUriPolicy::within(fs::absolute(file).parent_path()), report);
}

deform::Model load_gltf(const fs::path& file, const GltfUriPolicy& uris, LoadReport* report) {
  LoadReport local_report;
  LoadReport& out = report ? *report : local_report;
  out = LoadReport{};
  const tinygltf::Model gltf = parse_gltf_file(file, uris, &out);
  out.format = "glTF";
  out.generator = gltf.asset.generator;
  const AccessorReader reader(file, gltf);
  const NodeGraph graph = build_node_graph(reader, gltf);
  const int mesh_node = choose_skinned_node(reader, gltf, out);
  if (mesh_node < 0)
    reader.fail("no skinned mesh: " + std::to_string(gltf.meshes.size()) + " meshes, " +
                std::to_string(gltf.skins.size()) + " skins, but no node with both mesh and skin");
  const int skin_index = gltf.nodes[mesh_node].skin;
  const tinygltf::Skin& skin = gltf.skins[skin_index];
  const SkinSkeleton skeleton = build_skeleton(reader, gltf, skin, graph);
  out.source_joint_count = skeleton.skeleton.size();
  const std::vector<glm::dmat4> skinning = skinning_matrices(reader, skin, skeleton);
  ModelAssembler assembler(reader, skeleton, out);
  // Every mesh node in file order: skinned on the character's skin, or under one of its joints.
  std::uint32_t ordinal = 0;
  for (int node = 0; node < static_cast<int>(gltf.nodes.size()); ++node) {
    const int mesh_index = gltf.nodes[node].mesh;
    if (mesh_index < 0) continue;
    if (mesh_index >= static_cast<int>(gltf.meshes.size()))
      reader.fail("node " + std::to_string(node) + " refers to a missing mesh");
    const tinygltf::Mesh& mesh = gltf.meshes[mesh_index];
    MeshHandling handling{mesh_name(gltf, node), position_count(reader, mesh), -1, ""};
    const int skin_of_node = gltf.nodes[node].skin;
    const int joint = ancestor_joint(graph, skin, skeleton, node);
    std::vector<glm::dmat4> rigid;
    if (skin_of_node >= 0 && skin_of_node != skin_index)
      handling.ignored = "skinned to skin " + std::to_string(skin_of_node) +
                         ", not the character's skin " + std::to_string(skin_index);
    else if (skin_of_node < 0 && joint < 0)
      handling.ignored = "no skin, and not under a joint of the character's skin";
    else if (skin_of_node < 0)
      rigid.assign(skinning.size(), glm::dmat4(1.0)), rigid[joint] = graph.world[node];
    if (handling.ignored.empty()) {
      const NodeBinding binding = rigid.empty() ? NodeBinding{std::max(joint, 0), false, skinning}
                                                : NodeBinding{joint, true, rigid};
      const std::string mesh_what = "mesh " + std::to_string(mesh_index);
      handling.part = static_cast<int>(assembler.part_count());
      int last_mode = TINYGLTF_MODE_TRIANGLES;
      const int added = add_mesh_node(assembler, gltf, node, binding, ordinal, out, last_mode);
      if (node == mesh_node && mesh.primitives.empty())
        reader.fail("the skinned " + mesh_what + " has no primitives");
      if (node == mesh_node && added == 0)
        reader.fail("the skinned " + mesh_what + " has no triangle primitives (mode " +
                    std::to_string(last_mode) + "; only triangles, mode 4, are supported)");
      if (added == 0) handling.part = -1, handling.ignored = "no triangle primitives";
      ordinal += added > 0;
    }
    if (!handling.ignored.empty())
      out.warnings.push_back("mesh '" + handling.name + "' ignored: " + handling.ignored);
    out.meshes.push_back(std::move(handling));
  }
  deform::Model model = assembler.finish();
  model.name = file.stem().string();
  if (std::string why = model.validate(); !why.empty())
    reader.fail("the loaded model is invalid: " + why);
  return model;
}

}  // namespace sweepd::io
