#include "io/assimp/assimp_scene.h"

#include <assimp/commonMetaData.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>

#include <algorithm>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <cmath>
#include <set>
#include <string_view>

#include "io/assimp/assimp_crash_guard.h"
#include "io/files/load_error.h"
#include "io/rest_transform.h"

namespace sweepd::io::assimp {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kFbxBinaryMagic = "Kaydara FBX Binary";
// assimp names the nodes that hold an FBX joint's transform parts "<joint>_$AssimpFbx$_<part>".
constexpr std::string_view kHelperMarker = "_$AssimpFbx$_";
constexpr std::size_t kSniffBytes = 1024;

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

// Which FBX transform parts assimp kept as helper nodes of joints; all are collapsed.
void report_collapsed_helpers(const SceneNodes& nodes, const std::vector<int>& joint_of_node,
                              LoadReport& report) {
  std::map<std::string, int> joints_per_part;
  for (const aiNode* node : nodes.node) {
    const std::string_view name(node->mName.C_Str());
    const std::size_t marker = name.find(kHelperMarker);
    if (marker == std::string_view::npos) continue;
    const auto owner = nodes.by_name.find(std::string(name.substr(0, marker)));
    if (owner == nodes.by_name.end() || joint_of_node[owner->second] < 0) continue;
    ++joints_per_part[std::string(name.substr(marker + kHelperMarker.size()))];
  }
  if (joints_per_part.empty()) return;
  std::string parts;
  for (const auto& [part, count] : joints_per_part)
    parts += (parts.empty() ? "" : ", ") + part + " on " + std::to_string(count) + " joints";
  report.warnings.push_back(
      "FBX transform parts that assimp keeps as $AssimpFbx$ helper nodes (" + parts +
      ") were collapsed into their joints' rest transforms");
}

}  // namespace

RefusingFileSystem* configure_importer(Assimp::Importer& importer, bool animations) {
  auto* files = new RefusingFileSystem;  // the importer owns it
  importer.SetIOHandler(files);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, animations);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, true);
  return files;
}

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

const char* format_name(Format format) {
  return format == Format::kFbx ? "FBX" : format == Format::kCollada ? "COLLADA" : "unknown";
}

ImportedScene import_assimp_scene(std::span<const std::uint8_t> bytes, const fs::path& file,
                                  bool animations, LoadReport& report) {
  if (bytes.empty()) throw LoadError(file, "the file is empty");
  ImportedScene imported;
  imported.format = sniff(bytes);
  if (imported.format == Format::kUnknown)
    throw LoadError(file, "not an FBX (binary or ASCII) or COLLADA file");
  // libassimp can crash on a malformed file: tried in a child process first.
  if (const std::string crash = assimp_import_crash(bytes); !crash.empty())
    throw LoadError(file, crash);
  imported.importer = std::make_unique<Assimp::Importer>();
  Assimp::Importer& importer = *imported.importer;
  auto* files = configure_importer(importer, animations);
  const bool fbx = imported.format == Format::kFbx;
  imported.scene =
      importer.ReadFileFromMemory(bytes.data(), bytes.size(), kImportSteps, fbx ? "fbx" : "dae");
  const aiScene* scene = imported.scene;
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    std::string reason = importer.GetErrorString();
    if (reason.empty()) reason = "the importer returned an incomplete scene";
    throw LoadError(file, std::string("not a valid ") + format_name(imported.format) +
                              " file (corrupt or truncated): " + reason);
  }
  for (const std::string& path : files->refused)
    report.warnings.push_back("the file refers to '" + path +
                              "', which was not read (a model is read from its own bytes alone)");
  report.format = format_name(imported.format);
  imported.unit_scale = fbx ? fbx_unit_scale(file, *scene, report) : 1.0;
  return imported;
}

glm::dmat4 to_glm(const aiMatrix4x4& m, double unit_scale) {
  glm::dmat4 result;
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) result[column][row] = m[row][column];
  // Conjugating by the uniform unit scale S (S M S^-1) scales the translation alone.
  result[3] = glm::dvec4(glm::dvec3(result[3]) * unit_scale, 1.0);
  return result;
}

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

int bone_node(const SceneNodes& nodes, const aiBone* bone, const fs::path& file) {
  const auto it = nodes.by_name.find(bone->mName.C_Str());
  if (it == nodes.by_name.end())
    throw LoadError(file, "bone '" + std::string(bone->mName.C_Str()) +
                              "' names no node of the scene (no skeleton for the skin)");
  return it->second;
}

int helper_owner(const SceneNodes& nodes, int node) {
  const std::string_view name(nodes.node[node]->mName.C_Str());
  const std::size_t marker = name.find(kHelperMarker);
  if (marker == std::string_view::npos) return node;
  const auto owner = nodes.by_name.find(std::string(name.substr(0, marker)));
  return owner == nodes.by_name.end() ? -1 : owner->second;
}

Character find_character(const aiScene& scene, const SceneNodes& nodes, const fs::path& file,
                         LoadReport& report) {
  Character character;
  const int count = static_cast<int>(nodes.node.size());
  // Per skinned node, its bone nodes and their vertex count.
  std::vector<std::vector<int>> bones_of(count);
  std::vector<std::size_t> vertices_of(count, 0);
  for (int v = 0; v < count; ++v) {
    for (unsigned k = 0; k < nodes.node[v]->mNumMeshes; ++k) {
      const aiMesh* mesh = scene.mMeshes[nodes.node[v]->mMeshes[k]];
      vertices_of[v] += mesh->mNumVertices;
      for (unsigned b = 0; b < mesh->mNumBones; ++b)
        bones_of[v].push_back(bone_node(nodes, mesh->mBones[b], file));
    }
    if (bones_of[v].empty()) continue;
    ++report.skinned_mesh_count;
    if (character.body < 0 || vertices_of[v] > vertices_of[character.body]) character.body = v;
  }
  if (character.body < 0) return character;
  std::vector<char> is_bone(count, 0);
  for (int v = 0; v < count; ++v)
    for (const int bone : bones_of[v]) is_bone[bone] = 1;
  // A bone's root: its topmost ancestor that is a bone too.
  auto root_of = [&](int bone) {
    int root = bone;
    for (int v = nodes.parent[bone]; v >= 0; v = nodes.parent[v])
      if (is_bone[v]) root = v;
    return root;
  };
  std::set<int> roots;
  for (const int bone : bones_of[character.body]) roots.insert(root_of(bone));
  std::vector<char> is_joint(count, 0);  // the character's bones, for the rigid meshes' test
  for (int v = 0; v < count; ++v) {
    if (nodes.node[v]->mNumMeshes == 0) continue;
    CharacterMeshNode& mesh = character.meshes.emplace_back();
    mesh.node = v;
    if (bones_of[v].empty()) continue;
    for (const int bone : bones_of[v])
      if (!roots.count(root_of(bone))) mesh.ignored = "skinned to another skeleton";
    if (mesh.ignored.empty())
      for (const int bone : bones_of[v]) is_joint[bone] = 1, character.bones.push_back(bone);
  }
  for (CharacterMeshNode& mesh : character.meshes) {
    if (!bones_of[mesh.node].empty()) continue;
    mesh.rigid = true;
    int above = mesh.node;
    while (above >= 0 && !is_joint[above]) above = nodes.parent[above];
    if (above < 0) mesh.ignored = "no bones, and not under a joint of the character's skeleton";
  }
  return character;
}

AssimpSkeleton build_assimp_skeleton(const SceneNodes& nodes, std::span<const int> bone_nodes,
                                     const fs::path& file, LoadReport& report) {
  std::vector<char> is_bone(nodes.node.size(), 0);
  for (const int node : bone_nodes) is_bone[node] = 1;
  // Joints: the bones and, under each bone's nearest bone ancestor, the nodes in between.
  std::vector<char> is_joint = is_bone;
  for (int v = 0; v < static_cast<int>(nodes.node.size()); ++v) {
    if (!is_bone[v]) continue;
    int ancestor = nodes.parent[v];
    while (ancestor >= 0 && !is_bone[ancestor]) ancestor = nodes.parent[ancestor];
    if (ancestor < 0) continue;
    for (int between = nodes.parent[v]; between != ancestor; between = nodes.parent[between])
      if (!is_helper(nodes.node[between])) is_joint[between] = 1;
  }
  AssimpSkeleton result;
  deform::Skeleton& skeleton = result.skeleton;
  result.joint_of_node.assign(nodes.node.size(), -1);
  std::set<std::string> used_names;
  bool folded_above_root = false;
  for (int v = 0; v < static_cast<int>(nodes.node.size()); ++v) {
    if (!is_joint[v]) continue;
    int parent_node = nodes.parent[v];
    while (parent_node >= 0 && !is_joint[parent_node]) parent_node = nodes.parent[parent_node];
    deform::Joint joint;
    const std::string base = nodes.node[v]->mName.length == 0 ? "joint_" + std::to_string(v)
                                                              : nodes.node[v]->mName.C_Str();
    joint.name = base;
    for (int k = 2; !used_names.insert(joint.name).second; ++k)
      joint.name = base + "_" + std::to_string(k);
    joint.parent = parent_node < 0 ? -1 : result.joint_of_node[parent_node];
    // Above a root joint, past its own helper nodes: an armature or scene root transform.
    int above = nodes.parent[v];
    while (above >= 0 && is_helper(nodes.node[above])) above = nodes.parent[above];
    if (parent_node < 0 && above >= 0 && nodes.world[above] != glm::dmat4(1.0))
      folded_above_root = true;
    const glm::dmat4 local =
        parent_node < 0 ? nodes.world[v] : glm::inverse(nodes.world[parent_node]) * nodes.world[v];
    if (!decompose_rest_transform(local, joint))
      throw LoadError(file,
                      "joint '" + joint.name + "' has a degenerate (zero-scale) rest transform");
    if (!finite_rest_transform(joint))
      throw LoadError(file, "joint '" + joint.name +
                                "' has a rest transform that is not finite (NaN or Inf)");
    result.joint_of_node[v] = skeleton.size();
    result.joint_node.push_back(v);
    skeleton.joints.push_back(std::move(joint));
  }
  if (skeleton.size() > 65535)
    throw LoadError(file, "the skeleton has " + std::to_string(skeleton.size()) +
                              " joints (at most 65535)");
  report.source_joint_count = skeleton.size();
  report_collapsed_helpers(nodes, result.joint_of_node, report);
  if (folded_above_root)
    report.warnings.push_back(
        "the nodes above the root joint carry a transform (an armature's rotation or scale, or "
        "COLLADA's <unit>/<up_axis> applied by assimp); folded into the root joint's rest "
        "transform");
  return result;
}

}  // namespace sweepd::io::assimp
