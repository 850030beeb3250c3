#include "io/assimp_load.h"

#include <assimp/commonMetaData.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "io/bind_pose_vertices.h"
#include "io/file_bytes.h"
#include "io/rest_transform.h"

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kFbxBinaryMagic = "Kaydara FBX Binary";
// assimp names the nodes that hold an FBX joint's transform parts "<joint>_$AssimpFbx$_<part>".
constexpr std::string_view kHelperMarker = "_$AssimpFbx$_";
constexpr std::size_t kSniffBytes = 1024;

enum class Format { kFbx, kCollada, kUnknown };

Format sniff(std::span<const std::uint8_t> bytes) {
  const std::string_view head(reinterpret_cast<const char*>(bytes.data()),
                              std::min(bytes.size(), kSniffBytes));
  if (head.starts_with(kFbxBinaryMagic)) return Format::kFbx;
  const std::size_t text = head.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (text != std::string_view::npos && head.substr(text).starts_with("; FBX")) return Format::kFbx;
  if (head.find("FBXHeaderExtension") != std::string_view::npos) return Format::kFbx;
  if (head.find("<COLLADA") != std::string_view::npos) return Format::kCollada;
  return Format::kUnknown;
}

// Refuses every file, so assimp reads only the bytes it was handed (which its MemoryIOSystem
// serves before asking this one); remembers what it refused, for the report.
class RefusingFileSystem : public Assimp::IOSystem {
 public:
  explicit RefusingFileSystem(std::vector<std::string>& refused) : refused_(refused) {}
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char*) override {
    refused_.emplace_back(file);
    return nullptr;
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  std::vector<std::string>& refused_;
};

glm::dmat4 to_glm(const aiMatrix4x4& m, double unit_scale) {
  glm::dmat4 result;
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) result[column][row] = m[row][column];
  // Conjugating by the uniform unit scale S (S M S^-1) scales the translation alone.
  result[3] = glm::dvec4(glm::dvec3(result[3]) * unit_scale, 1.0);
  return result;
}

// A metadata number of any numeric type; `fallback` when absent.
double metadata_number(const aiMetadata* metadata, const char* key, double fallback) {
  if (!metadata) return fallback;
  for (unsigned i = 0; i < metadata->mNumProperties; ++i) {
    if (std::string_view(metadata->mKeys[i].C_Str()) != key) continue;
    const aiMetadataEntry& entry = metadata->mValues[i];
    switch (entry.mType) {
      case AI_BOOL:
        return *static_cast<const bool*>(entry.mData) ? 1.0 : 0.0;
      case AI_INT32:
        return *static_cast<const std::int32_t*>(entry.mData);
      case AI_UINT64:
        return static_cast<double>(*static_cast<const std::uint64_t*>(entry.mData));
      case AI_FLOAT:
        return *static_cast<const float*>(entry.mData);
      case AI_DOUBLE:
        return *static_cast<const double*>(entry.mData);
      default:
        return fallback;
    }
  }
  return fallback;
}

std::string metadata_string(const aiMetadata* metadata, const char* key) {
  aiString value;
  return metadata && metadata->Get(key, value) ? std::string(value.C_Str()) : std::string();
}

// The scene's nodes in depth-first pre-order (parents first) with parent and world matrices.
struct SceneNodes {
  std::vector<const aiNode*> node;
  std::vector<int> parent;
  std::vector<glm::dmat4> world;
  std::map<std::string, int> by_name;  // the first node of each name, as assimp's FindNode
};

SceneNodes scene_nodes(const aiScene& scene, double unit_scale) {
  SceneNodes nodes;
  std::vector<std::pair<const aiNode*, int>> stack{{scene.mRootNode, -1}};
  while (!stack.empty()) {
    const auto [node, parent] = stack.back();
    stack.pop_back();
    const int index = static_cast<int>(nodes.node.size());
    const glm::dmat4 local = to_glm(node->mTransformation, unit_scale);
    nodes.node.push_back(node);
    nodes.parent.push_back(parent);
    nodes.world.push_back(parent >= 0 ? nodes.world[parent] * local : local);
    nodes.by_name.emplace(node->mName.C_Str(), index);
    for (unsigned c = node->mNumChildren; c-- > 0;) stack.emplace_back(node->mChildren[c], index);
  }
  return nodes;
}

bool is_helper(const aiNode* node) {
  return std::string_view(node->mName.C_Str()).find(kHelperMarker) != std::string_view::npos;
}

// The node whose skinned meshes have the most vertices (-1 when none), with those meshes.
struct SkinnedNode {
  int node = -1;
  std::vector<const aiMesh*> meshes;
};

SkinnedNode choose_skinned_node(const aiScene& scene, const SceneNodes& nodes, LoadReport& report) {
  SkinnedNode best;
  std::size_t best_count = 0;
  for (int v = 0; v < static_cast<int>(nodes.node.size()); ++v) {
    SkinnedNode candidate{v, {}};
    std::size_t count = 0;
    for (unsigned k = 0; k < nodes.node[v]->mNumMeshes; ++k) {
      const aiMesh* mesh = scene.mMeshes[nodes.node[v]->mMeshes[k]];
      if (mesh->mNumBones == 0) continue;
      candidate.meshes.push_back(mesh);
      count += mesh->mNumVertices;
    }
    if (candidate.meshes.empty()) continue;
    ++report.skinned_mesh_count;
    if (best.node < 0 || count > best_count) best = std::move(candidate), best_count = count;
  }
  return best;
}

class AssimpModelReader {
 public:
  AssimpModelReader(const fs::path& file, const aiScene& scene, double unit_scale,
                    LoadReport& report)
      : file_(file),
        unit_scale_(unit_scale),
        report_(report),
        nodes_(scene_nodes(scene, unit_scale)),
        vertices_(model_, report) {}

  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(file_, reason); }

  const SceneNodes& nodes() const { return nodes_; }

  // The skeleton of the chosen node's bones; fills joint_of_node_.
  void build_skeleton(const SkinnedNode& skinned) {
    std::vector<char> is_bone(nodes_.node.size(), 0);
    for (const aiMesh* mesh : skinned.meshes)
      for (unsigned b = 0; b < mesh->mNumBones; ++b) is_bone[bone_node(mesh->mBones[b])] = 1;
    // Joints: the bones and, under each bone's nearest bone ancestor, the nodes in between.
    std::vector<char> is_joint = is_bone;
    for (int v = 0; v < static_cast<int>(nodes_.node.size()); ++v) {
      if (!is_bone[v]) continue;
      int ancestor = nodes_.parent[v];
      while (ancestor >= 0 && !is_bone[ancestor]) ancestor = nodes_.parent[ancestor];
      if (ancestor < 0) continue;
      for (int between = nodes_.parent[v]; between != ancestor; between = nodes_.parent[between])
        if (!is_helper(nodes_.node[between])) is_joint[between] = 1;
    }
    joint_of_node_.assign(nodes_.node.size(), -1);
    std::set<std::string> used_names;
    bool folded_above_root = false;
    for (int v = 0; v < static_cast<int>(nodes_.node.size()); ++v) {
      if (!is_joint[v]) continue;
      int parent_node = nodes_.parent[v];
      while (parent_node >= 0 && !is_joint[parent_node]) parent_node = nodes_.parent[parent_node];
      deform::Joint joint;
      const std::string base = nodes_.node[v]->mName.length == 0 ? "joint_" + std::to_string(v)
                                                                 : nodes_.node[v]->mName.C_Str();
      joint.name = base;
      for (int k = 2; !used_names.insert(joint.name).second; ++k)
        joint.name = base + "_" + std::to_string(k);
      joint.parent = parent_node < 0 ? -1 : joint_of_node_[parent_node];
      // Above a root joint, past its own helper nodes: an armature or scene root transform.
      int above = nodes_.parent[v];
      while (above >= 0 && is_helper(nodes_.node[above])) above = nodes_.parent[above];
      if (parent_node < 0 && above >= 0 && nodes_.world[above] != glm::dmat4(1.0))
        folded_above_root = true;
      const glm::dmat4 local = parent_node < 0
                                   ? nodes_.world[v]
                                   : glm::inverse(nodes_.world[parent_node]) * nodes_.world[v];
      if (!decompose_rest_transform(local, joint))
        fail("joint '" + joint.name + "' has a degenerate (zero-scale) rest transform");
      if (!finite_rest_transform(joint))
        fail("joint '" + joint.name + "' has a rest transform that is not finite (NaN or Inf)");
      joint_of_node_[v] = skeleton_.size();
      skeleton_.joints.push_back(std::move(joint));
    }
    if (skeleton_.size() > 65535)
      fail("the skeleton has " + std::to_string(skeleton_.size()) + " joints (at most 65535)");
    report_.source_joint_count = skeleton_.size();
    report_collapsed_helpers();
    if (folded_above_root)
      report_.warnings.push_back(
          "the nodes above the root joint carry a transform (an armature's rotation or scale, or "
          "COLLADA's <unit>/<up_axis> applied by assimp); folded into the root joint's rest "
          "transform");
  }

  void add_mesh(const aiMesh& mesh, int fallback_joint) {
    const std::size_t base = model_.positions.size();
    const std::size_t n = mesh.mNumVertices;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) {
        ++dropped_faces_;
        continue;
      }
      for (unsigned k = 0; k < 3; ++k)
        model_.indices.push_back(static_cast<std::uint32_t>(base + face.mIndices[k]));
    }
    // Per vertex: (joint, weight) pairs, and per bone the skinning matrix world * offset.
    std::vector<std::vector<std::pair<int, double>>> influences(n);
    std::vector<glm::dmat4> skinning(skeleton_.joints.size(), glm::dmat4(0.0));
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      const int node = bone_node(&bone);
      const int joint = joint_of_node_[node];
      skinning[joint] = nodes_.world[node] * to_glm(bone.mOffsetMatrix, unit_scale_);
      for (unsigned w = 0; w < bone.mNumWeights; ++w) {
        const aiVertexWeight& weight = bone.mWeights[w];
        if (weight.mVertexId >= n)
          fail("bone '" + std::string(bone.mName.C_Str()) + "' weights vertex " +
               std::to_string(weight.mVertexId) + " of " + std::to_string(n) + " (out of range)");
        if (!(weight.mWeight >= 0.0f) || !std::isfinite(weight.mWeight))
          fail("bone '" + std::string(bone.mName.C_Str()) + "' has an invalid weight " +
               std::to_string(weight.mWeight));
        if (weight.mWeight > 0.0f)
          add_influence(influences[weight.mVertexId], joint, weight.mWeight);
      }
    }
    for (std::size_t v = 0; v < n; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      const glm::dvec3 position = glm::dvec3(p.x, p.y, p.z) * unit_scale_;
      if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
        fail("vertex " + std::to_string(v) + " of mesh '" + mesh.mName.C_Str() +
             "' is not finite (NaN or Inf)");
      glm::dvec3 normal;
      if (mesh.HasNormals())
        normal = glm::dvec3(mesh.mNormals[v].x, mesh.mNormals[v].y, mesh.mNormals[v].z);
      // assimp's texture origin is bottom-left; deform::Model keeps glTF's top-left.
      glm::vec2 uv;
      if (mesh.HasTextureCoords(0))
        uv = glm::vec2(mesh.mTextureCoords[0][v].x, 1.0f - mesh.mTextureCoords[0][v].y);
      vertices_.append(influences[v], fallback_joint, skinning, position,
                       mesh.HasNormals() ? &normal : nullptr,
                       mesh.HasTextureCoords(0) ? &uv : nullptr);
    }
    ++report_.source_primitive_count;
  }

  deform::Model finish() {
    if (model_.indices.empty())
      fail("the skinned mesh has no triangles (" + std::to_string(dropped_faces_) +
           " points or lines only)");
    if (dropped_faces_ > 0)
      report_.warnings.push_back(std::to_string(dropped_faces_) +
                                 " faces of the skinned mesh were points or lines; dropped");
    vertices_.finish(skeleton_, "normal", "texture coordinates");
    model_.skeleton = skeleton_;
    return std::move(model_);
  }

  // The mesh node's nearest ancestor joint, else joint 0 (the first root).
  int fallback_joint(int mesh_node) const {
    for (int v = nodes_.parent[mesh_node]; v >= 0; v = nodes_.parent[v])
      if (joint_of_node_[v] >= 0) return joint_of_node_[v];
    return 0;
  }

 private:
  int bone_node(const aiBone* bone) const {
    const auto it = nodes_.by_name.find(bone->mName.C_Str());
    if (it == nodes_.by_name.end())
      fail("bone '" + std::string(bone->mName.C_Str()) +
           "' names no node of the scene (no skeleton for the skin)");
    return it->second;
  }

  // Which FBX transform parts assimp kept as helper nodes of joints; all are collapsed.
  void report_collapsed_helpers() {
    std::map<std::string, int> joints_per_part;
    for (const aiNode* node : nodes_.node) {
      const std::string_view name(node->mName.C_Str());
      const std::size_t marker = name.find(kHelperMarker);
      if (marker == std::string_view::npos) continue;
      const auto owner = nodes_.by_name.find(std::string(name.substr(0, marker)));
      if (owner == nodes_.by_name.end() || joint_of_node_[owner->second] < 0) continue;
      ++joints_per_part[std::string(name.substr(marker + kHelperMarker.size()))];
    }
    if (joints_per_part.empty()) return;
    std::string parts;
    for (const auto& [part, count] : joints_per_part)
      parts += (parts.empty() ? "" : ", ") + part + " on " + std::to_string(count) + " joints";
    report_.warnings.push_back(
        "FBX transform parts that assimp keeps as $AssimpFbx$ helper nodes (" + parts +
        ") were collapsed into their joints' rest transforms");
  }

  const fs::path& file_;
  double unit_scale_;
  LoadReport& report_;
  SceneNodes nodes_;
  deform::Skeleton skeleton_;
  std::vector<int> joint_of_node_;
  deform::Model model_;
  BindPoseVertices vertices_;
  std::size_t dropped_faces_ = 0;
};

// FBX's declared unit (centimetres per file unit, UnitScaleFactor) as metres per file unit, and
// its up axis, both reported; COLLADA's unit assimp applies itself (in the root node).
double fbx_unit_scale(const fs::path& file, const aiScene& scene, LoadReport& report) {
  const double centimetres = metadata_number(scene.mMetaData, "UnitScaleFactor", 1.0);
  if (!(centimetres > 0.0) || !std::isfinite(centimetres))
    throw LoadError(file, "UnitScaleFactor " + std::to_string(centimetres) + " is not a length");
  const double scale = centimetres / 100.0;
  if (scale != 1.0)
    report.warnings.push_back("the file's unit is " + std::to_string(centimetres) +
                              " cm (UnitScaleFactor); positions and joint translations scaled by " +
                              std::to_string(scale) + " to metres");
  const int up_axis = static_cast<int>(metadata_number(scene.mMetaData, "UpAxis", 1.0));
  const int up_sign = static_cast<int>(metadata_number(scene.mMetaData, "UpAxisSign", 1.0));
  if (up_axis != 1 || up_sign != 1)
    report.warnings.push_back(std::string("the file's up axis is ") + (up_sign < 0 ? "-" : "+") +
                              (up_axis == 0   ? "X"
                               : up_axis == 2 ? "Z"
                                              : "Y") +
                              " (UpAxis); not converted: sweepd expects +Y up");
  return scale;
}

}  // namespace

std::string_view assimp_model_suffix(std::span<const std::uint8_t> bytes) {
  switch (sniff(bytes)) {
    case Format::kFbx:
      return ".fbx";
    case Format::kCollada:
      return ".dae";
    default:
      return "";
  }
}

deform::Model load_assimp(const fs::path& file, LoadReport* report) {
  return load_assimp(read_file_bytes(file), file, report);
}

deform::Model load_assimp(std::span<const std::uint8_t> bytes, const fs::path& file,
                          LoadReport* report) {
  LoadReport local_report;
  LoadReport& out = report ? *report : local_report;
  out = LoadReport{};
  if (bytes.empty()) throw LoadError(file, "the file is empty");
  const Format format = sniff(bytes);
  if (format == Format::kUnknown)
    throw LoadError(file, "not an FBX (binary or ASCII) or COLLADA file");
  const char* format_name = format == Format::kFbx ? "FBX" : "COLLADA";

  std::vector<std::string> refused;  // outlives the importer, which owns the file system
  Assimp::Importer importer;
  importer.SetIOHandler(new RefusingFileSystem(refused));
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, true);
  const aiScene* scene = importer.ReadFileFromMemory(
      bytes.data(), bytes.size(), aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure,
      format == Format::kFbx ? "fbx" : "dae");
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    std::string reason = importer.GetErrorString();
    if (reason.empty()) reason = "the importer returned an incomplete scene";
    throw LoadError(file, std::string("not a valid ") + format_name +
                              " file (corrupt or truncated): " + reason);
  }
  for (const std::string& path : refused)
    out.warnings.push_back("the file refers to '" + path +
                           "', which was not read (a model is read from its own bytes alone)");
  out.format = format_name;
  out.generator = metadata_string(scene->mMetaData, AI_METADATA_SOURCE_GENERATOR);
  if (scene->mNumMeshes == 0) throw LoadError(file, "no mesh: the file holds no geometry");
  const double unit_scale = format == Format::kFbx ? fbx_unit_scale(file, *scene, out) : 1.0;

  AssimpModelReader reader(file, *scene, unit_scale, out);
  SkinnedNode skinned = choose_skinned_node(*scene, reader.nodes(), out);
  if (skinned.node < 0)
    reader.fail("no skin: " + std::to_string(scene->mNumMeshes) +
                " meshes but none has bones (a skinned mesh bound to a skeleton is needed)");
  if (out.skinned_mesh_count > 1)
    out.warnings.push_back(std::to_string(out.skinned_mesh_count) +
                           " nodes have a skinned mesh; loaded '" +
                           reader.nodes().node[skinned.node]->mName.C_Str() +
                           "' (the most vertices), ignored the others");
  std::size_t polygons = 0, faces_before = 0;
  for (const aiMesh* mesh : skinned.meshes)
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      polygons += mesh->mFaces[f].mNumIndices > 3;
      ++faces_before;
    }
  if (polygons > 0) {
    // In place: the nodes and meshes stay where they are; only the meshes' faces change.
    if (!importer.ApplyPostProcessing(aiProcess_Triangulate))
      reader.fail(std::string("triangulating the polygons failed: ") + importer.GetErrorString());
    std::size_t faces_after = 0;
    for (const aiMesh* mesh : skinned.meshes) faces_after += mesh->mNumFaces;
    out.warnings.push_back(std::to_string(polygons) +
                           " polygons with more than 3 corners were triangulated (" +
                           std::to_string(faces_after - faces_before + polygons) + " triangles)");
  }
  reader.build_skeleton(skinned);
  const int fallback = reader.fallback_joint(skinned.node);
  for (const aiMesh* mesh : skinned.meshes) reader.add_mesh(*mesh, fallback);
  deform::Model model = reader.finish();
  model.name = file.stem().string();
  if (std::string why = model.validate(); !why.empty())
    reader.fail("the loaded model is invalid: " + why);
  return model;
}

}  // namespace sweepd::io
