#include "io/gltf_save.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

namespace sweepd::io {

namespace {

// Collects one binary buffer and the buffer views / accessors that point into it.
class GlbBuilder {
 public:
  explicit GlbBuilder(tinygltf::Model& gltf) : gltf_(gltf) { gltf_.buffers.resize(1); }

  // Appends `count` elements of `type`/`component_type` from raw bytes; returns the accessor.
  template <typename T>
  int add_accessor(const std::vector<T>& elements, int component_type, int type, int target) {
    std::vector<unsigned char>& data = gltf_.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = elements.size() * sizeof(T);
    view.target = target;
    const auto* bytes = reinterpret_cast<const unsigned char*>(elements.data());
    data.insert(data.end(), bytes, bytes + view.byteLength);
    data.resize((data.size() + 3) / 4 * 4, 0);  // every view starts 4-byte aligned
    gltf_.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(gltf_.bufferViews.size()) - 1;
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = elements.size();
    gltf_.accessors.push_back(accessor);
    return static_cast<int>(gltf_.accessors.size()) - 1;
  }

 private:
  tinygltf::Model& gltf_;
};

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

std::map<std::string, int> add_vertex_attributes(GlbBuilder& builder, tinygltf::Model& gltf,
                                                 const deform::Model& model,
                                                 const SaveOptions& options) {
  std::map<std::string, int> attributes;
  attributes["POSITION"] = add_positions(builder, gltf, model.positions);
  std::vector<glm::vec3> normals(model.normals.size());
  for (std::size_t v = 0; v < normals.size(); ++v) {  // the validator wants unit length
    const float length = glm::length(model.normals[v]);
    normals[v] = length > 0.0f ? model.normals[v] / length : glm::vec3(0, 1, 0);
  }
  attributes["NORMAL"] = builder.add_accessor(normals, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                              TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (model.has_uvs())
    attributes["TEXCOORD_0"] = builder.add_accessor(
        model.uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!options.vertex_colors.empty())
    attributes["COLOR_0"] =
        builder.add_accessor(options.vertex_colors, TINYGLTF_COMPONENT_TYPE_FLOAT,
                             TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);

  std::vector<std::array<std::uint16_t, deform::kInfluences>> joints = model.skin_joints;
  std::vector<std::array<float, deform::kInfluences>> weights = model.skin_weights;
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

tinygltf::Model build_gltf(const deform::Model& model, const SaveOptions& options) {
  tinygltf::Model gltf;
  gltf.asset.version = "2.0";
  gltf.asset.generator = "sweepd";
  GlbBuilder builder(gltf);

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = 0;
  primitive.attributes = add_vertex_attributes(builder, gltf, model, options);
  primitive.indices =
      builder.add_accessor(model.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                           TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  gltf.materials.push_back(default_material());
  tinygltf::Mesh mesh;
  mesh.name = model.name;
  mesh.primitives.push_back(primitive);
  gltf.meshes.push_back(mesh);

  // Nodes 0..J-1 are the joints (same order as the skeleton), node J is the skinned mesh.
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
  if (scene.nodes.size() == 1) skin.skeleton = scene.nodes.front();
  skin.inverseBindMatrices =
      builder.add_accessor(inverse_bind, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, 0);
  gltf.skins.push_back(skin);
  tinygltf::Node mesh_node;
  mesh_node.name = model.name;
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  gltf.nodes.push_back(mesh_node);
  scene.nodes.push_back(joint_count);
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
    lines_node.mesh = 1;
    gltf.nodes.push_back(lines_node);
    scene.nodes.push_back(joint_count + 1);
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
  const tinygltf::Model gltf = build_gltf(model, options);
  std::ostringstream bytes;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&gltf, bytes, false, true))
    throw std::runtime_error("save_gltf " + file.string() + ": tinygltf could not serialise");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  const std::string content = bytes.str();
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out)
    throw std::runtime_error("save_gltf " + file.string() + ": cannot write the file (" +
                             std::strerror(errno) + ")");
}

}  // namespace sweepd::io
