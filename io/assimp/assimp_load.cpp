#include "io/assimp/assimp_load.h"

#include <assimp/commonMetaData.h>
#include <assimp/postprocess.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "io/assimp/assimp_scene.h"
#include "io/bind_pose_vertices.h"
#include "io/files/file_bytes.h"

namespace sweepd::io {

namespace {

namespace fs = std::filesystem;
using namespace assimp;

std::string metadata_string(const aiMetadata* metadata, const char* key) {
  aiString value;
  return metadata && metadata->Get(key, value) ? std::string(value.C_Str()) : std::string();
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

  // The skeleton of the character's bones.
  void build_skeleton(const Character& character) {
    skeleton_ = build_assimp_skeleton(nodes_, character.bones, file_, report_);
  }

  // Appends one assimp mesh of `node`: skinned by its bones (vertices without a bone on
  // `fallback_joint`), or rigid (weight 1 on `fallback_joint`, placed by the node's world
  // matrix). `part`, when given, receives its vertex and index ranges and goes into the model.
  void add_mesh(const aiMesh& mesh, int node, bool rigid, int fallback_joint,
                std::optional<deform::MeshPart> part) {
    if (part) {
      part->first_vertex = static_cast<std::uint32_t>(model_.positions.size());
      part->first_index = static_cast<std::uint32_t>(model_.indices.size());
      part->rigid_joint = rigid ? fallback_joint : -1;
    }
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
    std::vector<glm::dmat4> skinning(skeleton_.skeleton.joints.size(), glm::dmat4(0.0));
    if (rigid) skinning[fallback_joint] = nodes_.world[node];
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      const int node = bone_node(nodes_, &bone, file_);
      const int joint = skeleton_.joint_of_node[node];
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
    if (part) {
      part->vertex_count = static_cast<std::uint32_t>(model_.positions.size()) - part->first_vertex;
      part->index_count = static_cast<std::uint32_t>(model_.indices.size()) - part->first_index;
      model_.parts.push_back(std::move(*part));
    }
  }

  std::size_t part_count() const { return model_.parts.size(); }

  deform::Model finish() {
    if (model_.indices.empty())
      fail("the skinned mesh has no triangles (" + std::to_string(dropped_faces_) +
           " points or lines only)");
    if (dropped_faces_ > 0)
      report_.warnings.push_back(std::to_string(dropped_faces_) +
                                 " faces of the skinned mesh were points or lines; dropped");
    vertices_.finish(skeleton_.skeleton, "normal", "texture coordinates");
    model_.skeleton = skeleton_.skeleton;
    return std::move(model_);
  }

  // The mesh node's nearest joint (itself or an ancestor), else joint 0 (the first root).
  int fallback_joint(int mesh_node) const {
    for (int v = mesh_node; v >= 0; v = nodes_.parent[v])
      if (skeleton_.joint_of_node[v] >= 0) return skeleton_.joint_of_node[v];
    return 0;
  }

 private:
  const fs::path& file_;
  double unit_scale_;
  LoadReport& report_;
  SceneNodes nodes_;
  AssimpSkeleton skeleton_;
  deform::Model model_;
  BindPoseVertices vertices_;
  std::size_t dropped_faces_ = 0;
};

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
  const ImportedScene imported = import_assimp_scene(bytes, file, false, out);
  const aiScene* scene = imported.scene;
  out.generator = metadata_string(scene->mMetaData, AI_METADATA_SOURCE_GENERATOR);
  if (scene->mNumMeshes == 0) throw LoadError(file, "no mesh: the file holds no geometry");

  AssimpModelReader reader(file, *scene, imported.unit_scale, out);
  const Character character = find_character(*scene, reader.nodes(), file, out);
  if (character.body < 0)
    reader.fail("no skin: " + std::to_string(scene->mNumMeshes) +
                " meshes but none has bones (a skinned mesh bound to a skeleton is needed)");
  std::vector<const aiMesh*> loaded;  // every mesh of the character, in node order
  for (const CharacterMeshNode& node : character.meshes)
    if (node.ignored.empty())
      for (unsigned k = 0; k < reader.nodes().node[node.node]->mNumMeshes; ++k)
        loaded.push_back(scene->mMeshes[reader.nodes().node[node.node]->mMeshes[k]]);
  std::size_t polygons = 0, faces_before = 0;
  for (const aiMesh* mesh : loaded)
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      polygons += mesh->mFaces[f].mNumIndices > 3;
      ++faces_before;
    }
  if (polygons > 0) {
    // In place: the nodes and meshes stay where they are; only the meshes' faces change.
    if (!imported.importer->ApplyPostProcessing(aiProcess_Triangulate))
      reader.fail(std::string("triangulating the polygons failed: ") +
                  imported.importer->GetErrorString());
    std::size_t faces_after = 0;
    for (const aiMesh* mesh : loaded) faces_after += mesh->mNumFaces;
    out.warnings.push_back(std::to_string(polygons) +
                           " polygons with more than 3 corners were triangulated (" +
                           std::to_string(faces_after - faces_before + polygons) + " triangles)");
  }
  reader.build_skeleton(character);
  // One mesh: the model as before (no parts); several: a MeshPart each, as glTF's loader makes.
  const bool parts = loaded.size() > 1;
  std::uint32_t ordinal = 0;
  for (const CharacterMeshNode& node : character.meshes) {
    const aiNode& scene_node = *reader.nodes().node[node.node];
    MeshHandling handling{scene_node.mName.C_Str(), 0, -1, node.ignored};
    for (unsigned k = 0; k < scene_node.mNumMeshes; ++k)
      handling.vertex_count += scene->mMeshes[scene_node.mMeshes[k]]->mNumVertices;
    if (node.ignored.empty()) {
      const int joint = reader.fallback_joint(node.node);
      if (parts) handling.part = static_cast<int>(reader.part_count());
      for (unsigned k = 0; k < scene_node.mNumMeshes; ++k) {
        const aiMesh& mesh = *scene->mMeshes[scene_node.mMeshes[k]];
        std::optional<deform::MeshPart> part;
        if (parts) {
          part.emplace();
          part->name = handling.name;
          if (mesh.mMaterialIndex < scene->mNumMaterials)
            part->material = scene->mMaterials[mesh.mMaterialIndex]->GetName().C_Str();
          part->mesh = ordinal;
        }
        reader.add_mesh(mesh, node.node, node.rigid, joint, std::move(part));
      }
      ++ordinal;
    } else {
      out.warnings.push_back("mesh '" + handling.name + "' ignored: " + handling.ignored);
    }
    out.meshes.push_back(std::move(handling));
  }
  deform::Model model = reader.finish();
  model.name = file.stem().string();
  if (std::string why = model.validate(); !why.empty())
    reader.fail("the loaded model is invalid: " + why);
  return model;
}

}  // namespace sweepd::io
