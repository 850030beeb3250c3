#include "io/gltf/gltf_save.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/files/write_whole_file.h"
#include "io/gltf/glb_builder.h"
#include "io/gltf/gltf_animations_save.h"

namespace sweepd::io {

namespace {

// Unit weights as floats whose float32 running sum is within the validator's 2e-7 per
// non-zero weight of 1; repeated joints are merged and unused slots point at joint 0.
void normalise_influences(std::array<std::uint16_t, deform::kInfluences>& joints,
                          std::array<float, deform::kInfluences>& weights) {
  for (int k = 0; k < deform::kInfluences; ++k)
    for (int l = 0; l < k; ++l)
      if (weights[k] > 0.0f && weights[l] > 0.0f && joints[k] == joints[l]) {
        weights[l] += weights[k];
        weights[k] = 0.0f;
      }
  double sum = 0.0;
  for (float w : weights) sum += w;
  int largest = 0;
  for (int k = 0; k < deform::kInfluences; ++k) {
    weights[k] = static_cast<float>(weights[k] / sum);
    if (weights[k] > weights[largest]) largest = k;
    if (weights[k] == 0.0f) joints[k] = 0;
  }
  for (int attempt = 0; attempt < 4; ++attempt) {
    float running = 0.0f;
    int nonzero = 0;
    for (float w : weights)
      if (w != 0.0f) running += w, ++nonzero;
    if (std::abs(static_cast<double>(running) - 1.0) <= 2e-7 * nonzero) return;
    weights[largest] += 1.0f - running;
  }
}

tinygltf::Node joint_node(const deform::Joint& joint) {
  tinygltf::Node node;
  node.name = joint.name;
  const glm::vec3& t = joint.rest_translation;
  const glm::quat r = glm::normalize(joint.rest_rotation);  // the validator wants unit
  const glm::vec3& s = joint.rest_scale;
  node.translation = {t.x, t.y, t.z};
  node.rotation = {r.x, r.y, r.z, r.w};
  node.scale = {s.x, s.y, s.z};
  return node;
}

tinygltf::Material default_material() {
  tinygltf::Material material;
  material.name = "skin";
  material.pbrMetallicRoughness.baseColorFactor = {0.8, 0.62, 0.52, 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.7;
  return material;
}

// A POSITION accessor with the min/max bounds glTF requires for it.
int add_positions(GlbBuilder& builder, tinygltf::Model& gltf,
                  const std::vector<glm::vec3>& positions) {
  const int accessor = builder.add_accessor(positions, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                            TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  glm::vec3 low(std::numeric_limits<float>::max()), high(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : positions) low = glm::min(low, p), high = glm::max(high, p);
  gltf.accessors[accessor].minValues = {low.x, low.y, low.z};
  gltf.accessors[accessor].maxValues = {high.x, high.y, high.z};
  return accessor;
}

// The vertices [first, first + count) of the model, and for a rigid part the matrix that takes
// them from world space into its joint's (identity otherwise).
struct VertexRange {
  std::size_t first, count;
  glm::mat4 to_local{1.0f};
  bool rigid = false;

  template <typename T>
  std::vector<T> of(const std::vector<T>& values) const {
    return std::vector<T>(values.begin() + first, values.begin() + first + count);
  }
};

std::map<std::string, int> add_vertex_attributes(GlbBuilder& builder, tinygltf::Model& gltf,
                                                 const deform::Model& model,
                                                 const SaveOptions& options,
                                                 const VertexRange& range) {
  std::map<std::string, int> attributes;
  std::vector<glm::vec3> positions = range.of(model.positions);
  std::vector<glm::vec3> normals = range.of(model.normals);
  if (range.rigid) {
    const glm::mat3 turn = glm::mat3(range.to_local);
    for (std::size_t v = 0; v < positions.size(); ++v) {
      positions[v] = glm::vec3(range.to_local * glm::vec4(positions[v], 1.0f));
      normals[v] = turn * normals[v];
    }
  }
  attributes["POSITION"] = add_positions(builder, gltf, positions);
  for (glm::vec3& normal : normals) {  // the validator wants unit length
    const float length = glm::length(normal);
    normal = length > 0.0f ? normal / length : glm::vec3(0, 1, 0);
  }
  attributes["NORMAL"] = builder.add_accessor(normals, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                              TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (model.has_uvs())
    attributes["TEXCOORD_0"] =
        builder.add_accessor(range.of(model.uvs), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2,
                             TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!options.vertex_colors.empty())
    attributes["COLOR_0"] =
        builder.add_accessor(range.of(options.vertex_colors), TINYGLTF_COMPONENT_TYPE_FLOAT,
                             TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (range.rigid) return attributes;  // it follows its node, a child of its joint

  std::vector<std::array<std::uint16_t, deform::kInfluences>> joints = range.of(model.skin_joints);
  std::vector<std::array<float, deform::kInfluences>> weights = range.of(model.skin_weights);
  for (std::size_t v = 0; v < joints.size(); ++v) normalise_influences(joints[v], weights[v]);
  if (model.skeleton.size() <= 256) {
    std::vector<std::array<std::uint8_t, deform::kInfluences>> narrow(joints.size());
    for (std::size_t v = 0; v < joints.size(); ++v)
      for (int k = 0; k < deform::kInfluences; ++k)
        narrow[v][k] = static_cast<std::uint8_t>(joints[v][k]);
    attributes["JOINTS_0"] = builder.add_accessor(narrow, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                                  TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  } else {
    attributes["JOINTS_0"] = builder.add_accessor(joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                                  TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  }
  attributes["WEIGHTS_0"] = builder.add_accessor(weights, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                 TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
  return attributes;
}

// One material per distinct part material name, in first-seen order (an unnamed part's is the
// default "skin"); returns each part's material index.
std::vector<int> add_materials(tinygltf::Model& gltf, const std::vector<deform::MeshPart>& parts) {
  std::vector<int> material_of;
  for (const deform::MeshPart& part : parts) {
    tinygltf::Material material = default_material();
    if (!part.material.empty()) material.name = part.material;
    const auto same = std::find_if(gltf.materials.begin(), gltf.materials.end(),
                                   [&](const auto& m) { return m.name == material.name; });
    material_of.push_back(static_cast<int>(same - gltf.materials.begin()));
    if (same == gltf.materials.end()) gltf.materials.push_back(material);
  }
  return material_of;
}

tinygltf::Model build_gltf(const deform::Model& model, const SaveOptions& options) {
  tinygltf::Model gltf;
  gltf.asset.version = "2.0";
  gltf.asset.generator = "sweepd";
  GlbBuilder builder(gltf);

  // Nodes 0..J-1 are the joints (same order as the skeleton), then one node per mesh.
  const int joint_count = model.skeleton.size();
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  std::vector<glm::mat4> inverse_bind(joint_count);
  tinygltf::Skin skin;
  tinygltf::Scene scene;
  for (int j = 0; j < joint_count; ++j) {
    gltf.nodes.push_back(joint_node(model.skeleton.joints[j]));
    const int parent = model.skeleton.joints[j].parent;
    (parent < 0 ? scene.nodes : gltf.nodes[parent].children).push_back(j);
    skin.joints.push_back(j);
    inverse_bind[j] = glm::mat4(glm::inverse(glm::dmat4(world[j])));
  }

  const std::vector<int> roots = scene.nodes;

  // Parts of one file mesh (one `mesh` value, consecutive) become one mesh's primitives.
  const std::vector<deform::MeshPart> parts = model.meshes();
  const std::vector<int> material_of = add_materials(gltf, parts);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const deform::MeshPart& part = parts[k];
    const bool rigid = part.rigid_joint >= 0;
    VertexRange range{part.first_vertex, part.vertex_count};
    if (rigid) range.to_local = inverse_bind[part.rigid_joint], range.rigid = true;
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = material_of[k];
    primitive.attributes = add_vertex_attributes(builder, gltf, model, options, range);
    std::vector<std::uint32_t> indices(model.indices.begin() + part.first_index,
                                       model.indices.begin() + part.first_index + part.index_count);
    for (std::uint32_t& index : indices) index -= part.first_vertex;
    primitive.indices =
        builder.add_accessor(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                             TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    if (k > 0 && parts[k - 1].mesh == part.mesh) {
      gltf.meshes.back().primitives.push_back(primitive);
      continue;
    }
    tinygltf::Mesh mesh;
    mesh.name = part.name.empty() ? model.name : part.name;
    mesh.primitives.push_back(primitive);
    gltf.meshes.push_back(mesh);
    tinygltf::Node mesh_node;
    mesh_node.name = mesh.name;
    mesh_node.mesh = static_cast<int>(gltf.meshes.size()) - 1;
    const int node = static_cast<int>(gltf.nodes.size());
    if (rigid) {
      gltf.nodes[part.rigid_joint].children.push_back(node);
    } else {
      mesh_node.skin = 0;
      scene.nodes.push_back(node);
    }
    gltf.nodes.push_back(mesh_node);
  }
  if (roots.size() == 1) skin.skeleton = roots.front();
  skin.inverseBindMatrices =
      builder.add_accessor(inverse_bind, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, 0);
  gltf.skins.push_back(skin);
  add_animations(builder, gltf, options.animations);
  if (!options.line_loops.empty()) {  // one unskinned mesh of LINE_LOOP primitives
    tinygltf::Mesh lines;
    lines.name = "line loops";
    for (const std::vector<glm::vec3>& loop : options.line_loops) {
      tinygltf::Primitive primitive;
      primitive.mode = TINYGLTF_MODE_LINE_LOOP;
      primitive.material = 0;
      primitive.attributes["POSITION"] = add_positions(builder, gltf, loop);
      lines.primitives.push_back(primitive);
    }
    gltf.meshes.push_back(lines);
    tinygltf::Node lines_node;
    lines_node.name = "line loops";
    lines_node.mesh = static_cast<int>(gltf.meshes.size()) - 1;
    scene.nodes.push_back(static_cast<int>(gltf.nodes.size()));
    gltf.nodes.push_back(lines_node);
  }
  gltf.scenes.push_back(scene);
  gltf.defaultScene = 0;
  gltf.buffers[0].name = "sweepd";
  return gltf;
}

}  // namespace

void save_gltf(const deform::Model& model, const std::filesystem::path& file,
               const SaveOptions& options) {
  if (std::string why = model.validate(); !why.empty())
    throw std::invalid_argument("save_gltf " + file.string() + ": invalid model: " + why);
  for (const auto& loop : options.line_loops)
    if (loop.size() < 2)
      throw std::invalid_argument("save_gltf " + file.string() + ": a line loop needs 2 points");
  if (!options.vertex_colors.empty() && options.vertex_colors.size() != model.vertex_count())
    throw std::invalid_argument(
        "save_gltf " + file.string() + ": " + std::to_string(options.vertex_colors.size()) +
        " vertex colours for " + std::to_string(model.vertex_count()) + " vertices");
  if (std::string why = animations_problem(options.animations, model.skeleton); !why.empty())
    throw std::invalid_argument("save_gltf " + file.string() + ": " + why);
  const tinygltf::Model gltf = build_gltf(model, options);
  std::ostringstream bytes;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&gltf, bytes, false, true))
    throw std::runtime_error("save_gltf " + file.string() + ": tinygltf could not serialise");
  write_whole_file(file, bytes.str(), "save_gltf");
}

}  // namespace sweepd::io
