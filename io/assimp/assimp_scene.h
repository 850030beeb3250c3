// What reading a file through libassimp shares between the model reader (io/assimp/assimp_load.h) and
// the clip reader (io/assimp/assimp_clip_load.h), so that a clip read from a file has exactly the joints
// of the model read from it: the import itself, the scene's nodes, the skinned node and its
// skeleton. Internal to io/.
//
// import_assimp_scene(bytes, file, animations, report)
//   Input:  bytes       an FBX (binary or ASCII) or COLLADA file's content; assimp reads these and
//                       no other file: every other path it asks for is refused and named in a
//                       report warning
//           animations  whether FBX animation stacks are read (the model reader skips them)
//   The bytes are first tried in a child process (io/assimp/assimp_crash_guard.h): an importer crash is
//   a LoadError naming it, not the caller's death.
//   Output: the importer (which owns the scene), the scene, its format and, for FBX, its unit as
//           metres per file unit (UnitScaleFactor / 100, reported when not 1; an up axis other
//           than +Y reported, not converted). Throws LoadError naming the file: empty, not FBX or
//           COLLADA, corrupt or truncated (assimp's reason).
// scene_nodes(scene, unit_scale): the nodes depth-first, parents first, with parent indices,
//   world matrices (translations in metres) and the first node of each name.
// find_character: the character's mesh nodes and bones. The skinned node with the most vertices
//   is the body; every other node with skinned meshes whose bones hang from the same root bones
//   is part of the character too (a Mixamo body of two meshes, eyes and teeth on the same
//   skeleton); a node with meshes but no bones under one of the character's joints is rigid to
//   it (a helmet, a prop); every other mesh node is ignored, with the reason. Nodes with a skinned
//   mesh are counted in report.skinned_mesh_count. bones: every bone of the skinned nodes.
// helper_owner: the joint node a "<joint>_$AssimpFbx$_<part>" helper node belongs to (the node
//   itself when it is no helper; -1 when its owner is missing).
// build_assimp_skeleton: the joints of a set of bone nodes — the bones and the non-helper
//   nodes between a bone and its nearest bone ancestor, parents first; FBX transform parts that
//   assimp keeps as "<joint>_$AssimpFbx$_<part>" helper nodes (PreRotation, RotationPivot, ...)
//   are collapsed into their joint's rest transform (reported per part); nodes above a root are
//   folded into it (reported). The model's bones are find_character's; a clip file without a skin
//   (an animation exported alone) uses the owners of its animated nodes. joint_of_node: per scene node, its joint or -1; joint_node: per
//   joint, its node. Throws LoadError: a bone naming no node, a degenerate or non-finite rest
//   transform, more than 65535 joints.
#pragma once

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>

#include <assimp/Importer.hpp>
#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "deform/model/skeleton.h"
#include "io/load_report.h"

namespace sweepd::io::assimp {

enum class Format { kFbx, kCollada, kUnknown };

// What the bytes start like (the first KiB).
Format sniff(std::span<const std::uint8_t> bytes);
const char* format_name(Format format);

// Refuses every file, so assimp reads only the bytes it was handed (which its MemoryIOSystem
// serves before asking this one); remembers what it refused, for the report.
class RefusingFileSystem : public Assimp::IOSystem {
 public:
  bool Exists(const char*) const override { return false; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char*) override {
    refused.emplace_back(file);
    return nullptr;
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

  std::vector<std::string> refused;
};

// The post-processing steps of every import: vertices joined, the structure validated.
inline constexpr unsigned kImportSteps =
    aiProcess_JoinIdenticalVertices | aiProcess_ValidateDataStructure;

// The importer set up as every import here runs it: no other file read (the returned file
// system, which the importer owns, lists what was refused), no textures, cameras or lights,
// FBX pivots kept as helper nodes, animations read or not.
RefusingFileSystem* configure_importer(Assimp::Importer& importer, bool animations);

struct ImportedScene {
  std::unique_ptr<Assimp::Importer> importer;
  const aiScene* scene = nullptr;  // owned by importer
  Format format = Format::kUnknown;
  double unit_scale = 1.0;  // metres per file unit
};

ImportedScene import_assimp_scene(std::span<const std::uint8_t> bytes,
                                  const std::filesystem::path& file, bool animations,
                                  LoadReport& report);

// assimp's row-major matrix as glm's, its translation times unit_scale.
glm::dmat4 to_glm(const aiMatrix4x4& m, double unit_scale);

struct SceneNodes {
  std::vector<const aiNode*> node;
  std::vector<int> parent;
  std::vector<glm::dmat4> world;
  std::map<std::string, int> by_name;  // the first node of each name, as assimp's FindNode
};

SceneNodes scene_nodes(const aiScene& scene, double unit_scale);

bool is_helper(const aiNode* node);

struct CharacterMeshNode {
  int node = -1;
  bool rigid = false;   // no bones: follows the joint above it
  std::string ignored;  // why the node is not part of the character; empty when it is
};

struct Character {
  int body = -1;                          // the skinned node with the most vertices; -1: none
  std::vector<CharacterMeshNode> meshes;  // every node with meshes, depth-first (file) order
  std::vector<int> bones;                 // the skinned nodes' bone nodes
};

Character find_character(const aiScene& scene, const SceneNodes& nodes,
                         const std::filesystem::path& file, LoadReport& report);

struct AssimpSkeleton {
  deform::Skeleton skeleton;
  std::vector<int> joint_of_node;
  std::vector<int> joint_node;
};

// The scene node a bone names; LoadError when none.
int bone_node(const SceneNodes& nodes, const aiBone* bone, const std::filesystem::path& file);
int helper_owner(const SceneNodes& nodes, int node);

AssimpSkeleton build_assimp_skeleton(const SceneNodes& nodes, std::span<const int> bone_nodes,
                                     const std::filesystem::path& file, LoadReport& report);

}  // namespace sweepd::io::assimp
