#include "io/gltf_load.h"

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
#include "io/gltf_guarded_files.h"
#include "io/rest_transform.h"

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;

std::string trimmed(std::string text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  return text;
}

std::string type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "type " + std::to_string(type);
  }
}

double max_of_integer_type(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return 127.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 255.0;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return 32767.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 65535.0;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return 4294967295.0;
    default:
      return 1.0;
  }
}

template <typename T>
double decode_as(const unsigned char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return static_cast<double>(value);
}

double decode_component(const unsigned char* bytes, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return decode_as<std::int8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return decode_as<std::uint8_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return decode_as<std::int16_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return decode_as<std::uint16_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return decode_as<std::uint32_t>(bytes);
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return decode_as<float>(bytes);
    default:
      return 0.0;
  }
}

// What a caller accepts from one accessor.
struct AccessorSpec {
  std::string what;  // e.g. "POSITION of mesh 0 primitive 1", for messages
  int type;          // TINYGLTF_TYPE_*
  std::vector<int> component_types;
  bool normalize_integers;  // map integer components to [0, 1] / [-1, 1]
};

// Reads glTF accessors (byteStride, sparse, normalised integers) with every bound checked, and
// turns each problem into a LoadError naming the file.
class AccessorReader {
 public:
  AccessorReader(const fs::path& file, const tinygltf::Model& gltf) : file_(file), gltf_(gltf) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(file_, reason); }

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(gltf_.accessors.size()))
      fail(what + ": accessor " + std::to_string(index) + " does not exist");
    return gltf_.accessors[index];
  }

  // count * components values, as doubles, in element order.
  std::vector<double> read(int index, const AccessorSpec& spec) const {
    const tinygltf::Accessor& acc = accessor(index, spec.what);
    const std::string where = spec.what + " (accessor " + std::to_string(index) + ")";
    if (acc.type != spec.type)
      fail(where + " has type " + type_name(acc.type) + ", expected " + type_name(spec.type));
    if (std::find(spec.component_types.begin(), spec.component_types.end(), acc.componentType) ==
        spec.component_types.end())
      fail(where + " has unsupported component type " + std::to_string(acc.componentType));
    const int components = tinygltf::GetNumComponentsInType(acc.type);
    const std::size_t component_size = tinygltf::GetComponentSizeInBytes(acc.componentType);
    const std::size_t element_size = components * component_size;
    // Bounds first, so that a lying count cannot make us allocate before failing.
    ElementRange range{nullptr, 0, 0};
    if (acc.bufferView >= 0)
      range = locate(acc.bufferView, acc.byteOffset, 0, element_size, acc.count, where);
    else if (acc.count > kMaxElementsWithoutData)
      fail(where + " has count " + std::to_string(acc.count) + " but no buffer view");
    std::vector<double> values(acc.count * components, 0.0);
    for (std::size_t i = 0; i < range.count; ++i)
      for (int c = 0; c < components; ++c)
        values[i * components + c] =
            decode_component(range.element(i) + c * component_size, acc.componentType);
    if (acc.sparse.isSparse) apply_sparse(acc, where, components, component_size, values);
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        fail(where + " element " + std::to_string(i / components) + " is not finite (NaN or Inf)");
    if (spec.normalize_integers && acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
      const double scale = max_of_integer_type(acc.componentType);
      for (double& value : values) value = std::max(value / scale, -1.0);  // spec: max(c/m, -1)
    }
    return values;
  }

 private:
  // An accessor's elements may be all zeros with no buffer view; cap how many we accept then.
  static constexpr std::size_t kMaxElementsWithoutData = std::size_t{1} << 22;

  // `count` elements laid out `stride` bytes apart from `base`, all inside the buffer.
  struct ElementRange {
    const unsigned char* base;
    std::size_t stride;
    std::size_t count;
    const unsigned char* element(std::size_t i) const { return base + i * stride; }
  };

  // Checks that `count` elements of `element_size` bytes at `offset` fit in the view and the
  // view in its buffer; stride 0 means the view's byteStride (or tightly packed).
  ElementRange locate(int view_index, std::size_t offset, std::size_t stride,
                      std::size_t element_size, std::size_t count, const std::string& where) const {
    if (view_index < 0 || view_index >= static_cast<int>(gltf_.bufferViews.size()))
      fail(where + " refers to missing buffer view " + std::to_string(view_index));
    const tinygltf::BufferView& view = gltf_.bufferViews[view_index];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(gltf_.buffers.size()))
      fail(where + ": buffer view " + std::to_string(view_index) + " refers to missing buffer " +
           std::to_string(view.buffer));
    const std::vector<unsigned char>& data = gltf_.buffers[view.buffer].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      fail(where + ": buffer view " + std::to_string(view_index) + " runs past the end of buffer " +
           std::to_string(view.buffer) + " (" + std::to_string(data.size()) +
           " bytes; missing or truncated buffer data)");
    if (stride == 0) stride = view.byteStride != 0 ? view.byteStride : element_size;
    if (stride < element_size)
      fail(where + " has byteStride " + std::to_string(stride) + " below its element size " +
           std::to_string(element_size));
    const unsigned char* base = data.data() + view.byteOffset;
    if (count == 0) return {base, stride, 0};
    // count <= byteLength keeps the product below from overflowing (elements are >= 1 byte).
    if (count > view.byteLength || offset > view.byteLength ||
        stride * (count - 1) + element_size > view.byteLength - offset)
      fail(where + " has " + std::to_string(count) + " elements of " +
           std::to_string(element_size) + " bytes (stride " + std::to_string(stride) +
           ") that do not fit in buffer view " + std::to_string(view_index) + " of " +
           std::to_string(view.byteLength) + " bytes (out of range)");
    return {base + offset, stride, count};
  }

  void apply_sparse(const tinygltf::Accessor& acc, const std::string& where, int components,
                    std::size_t component_size, std::vector<double>& values) const {
    const auto& sparse = acc.sparse;
    const int index_type = sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(where + " has sparse indices of unsupported component type " +
           std::to_string(index_type));
    if (sparse.count < 0) fail(where + " has a negative sparse count");
    const std::size_t count = static_cast<std::size_t>(sparse.count);
    const std::string sparse_where = where + " sparse";
    const std::size_t index_size = tinygltf::GetComponentSizeInBytes(index_type);
    const std::size_t element_size = components * component_size;
    const ElementRange indices = locate(sparse.indices.bufferView, sparse.indices.byteOffset,
                                        index_size, index_size, count, sparse_where + " indices");
    const ElementRange replacements =
        locate(sparse.values.bufferView, sparse.values.byteOffset, element_size, element_size,
               count, sparse_where + " values");
    for (std::size_t i = 0; i < count; ++i) {
      const double target = decode_component(indices.element(i), index_type);
      if (target >= static_cast<double>(acc.count))
        fail(sparse_where + " index " + std::to_string(i) + " is out of range");
      const std::size_t element = static_cast<std::size_t>(target);
      for (int c = 0; c < components; ++c)
        values[element * components + c] =
            decode_component(replacements.element(i) + c * component_size, acc.componentType);
    }
  }

  const fs::path& file_;
  const tinygltf::Model& gltf_;
};

const std::vector<int> kFloat = {TINYGLTF_COMPONENT_TYPE_FLOAT};
const std::vector<int> kFloatOrUnorm = {TINYGLTF_COMPONENT_TYPE_FLOAT,
                                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
const std::vector<int> kJointTypes = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
const std::vector<int> kIndexTypes = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;  // textures play no part in deformation; do not decode them
}

tinygltf::Model parse_file(const fs::path& file, const GltfUriPolicy& uris, LoadReport* report) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw LoadError(file, "cannot open the file (missing or unreadable)");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(stream)),
                                         std::istreambuf_iterator<char>());
  if (bytes.empty()) throw LoadError(file, "the file is empty");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (binary) {
    std::uint32_t declared = 0;
    if (bytes.size() >= 12) std::memcpy(&declared, bytes.data() + 8, 4);
    if (bytes.size() < 12)
      throw LoadError(file, "not a valid .glb: truncated inside the 12-byte header");
    if (declared > bytes.size())
      throw LoadError(file, "not a valid .glb: truncated (the header declares " +
                                std::to_string(declared) + " bytes, the file has " +
                                std::to_string(bytes.size()) + ")");
  }
  tinygltf::TinyGLTF parser;
  parser.SetImageLoader(skip_image, nullptr);
  GltfGuardedFiles files(uris);
  parser.SetFsCallbacks(files.callbacks());
  tinygltf::Model gltf;
  std::string error, warning;
  const std::string& base_dir = files.base_dir();
  const bool ok =
      binary ? parser.LoadBinaryFromMemory(&gltf, &error, &warning, bytes.data(),
                                           static_cast<unsigned int>(bytes.size()), base_dir)
             : parser.LoadASCIIFromString(&gltf, &error, &warning,
                                          reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned int>(bytes.size()), base_dir);
  // Before tinygltf's own message, which may just say "File not found", and also when only an
  // image was refused (tinygltf merely warns about images).
  if (std::string refusal = files.refusal(); !refusal.empty()) throw LoadError(file, refusal);
  if (!ok) {
    std::string reason = trimmed(error.empty() ? warning : error);
    if (reason.empty()) reason = "malformed glTF (e.g. a non-integer where an index belongs)";
    if (reason.find("parse_error") != std::string::npos) reason = "invalid JSON: " + reason;
    throw LoadError(file,
                    std::string(binary ? "not a valid .glb" : "not a valid .gltf") + ": " + reason);
  }
  if (report && !trimmed(warning).empty()) report->warnings.push_back(trimmed(warning));
  return gltf;
}

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

// The node graph: parent per node and world matrices, with bad references rejected.
struct NodeGraph {
  std::vector<int> parent;
  std::vector<glm::dmat4> world;
};

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

// Vertices of the mesh's primitives, as their POSITION accessors count them.
std::size_t position_count(const AccessorReader& reader, const tinygltf::Mesh& mesh) {
  std::size_t count = 0;
  for (const tinygltf::Primitive& primitive : mesh.primitives)
    if (auto it = primitive.attributes.find("POSITION"); it != primitive.attributes.end())
      count += reader.accessor(it->second, "POSITION").count;
  return count;
}

// The node with mesh and skin whose mesh has the most vertices; -1 when none: its skin is the
// character's.
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

// The skin's joints as a parents-first Skeleton; order[new] = old skin slot.
struct SkinSkeleton {
  deform::Skeleton skeleton;
  std::vector<int> new_index;  // per skin slot
  std::vector<int> order;      // per new joint: its skin slot
};

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
  const tinygltf::Model gltf = parse_file(file, uris, &out);
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
