// Model: a rigged, skinned triangle mesh in its rest ("dress") pose — the input to binding.
//
// Invariants every loader and generator establishes (Model::validate checks them):
// - positions are world-space rest positions (metres, Y up); normals unit length, same count;
// - uvs are empty or one per vertex; indices hold triangles (size % 3 == 0), all in range;
// - skin_joints/skin_weights hold 4 influences per vertex, weights >= 0 summing to 1,
//   joint indices < skeleton.size();
// - the skeleton's world rest matrices are the bind matrices: skinning with the rest pose is
//   the identity, so no inverse bind matrices are stored (loaders bake the file's ones in);
// - parts are empty (one mesh) or cover the vertices and indices in order (mesh_part.h).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "deform/model/mesh_part.h"
#include "deform/model/skeleton.h"

namespace sweepd::deform {

inline constexpr int kInfluences = 4;

struct Model {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;          // empty when the model has none
  std::vector<std::uint32_t> indices;  // triangles
  Skeleton skeleton;
  std::vector<std::array<std::uint16_t, kInfluences>> skin_joints;
  std::vector<std::array<float, kInfluences>> skin_weights;
  std::vector<MeshPart> parts;  // the file's meshes, when it had several kinds or pieces

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return indices.size() / 3; }
  bool has_uvs() const { return !uvs.empty(); }
  // Vertex v's strongest influence: the slot (0 .. kInfluences-1) of its largest skin weight,
  // the first of equal ones.
  int strongest_influence(std::size_t v) const;
  // The joint of that influence.
  int strongest_joint(std::size_t v) const { return skin_joints[v][strongest_influence(v)]; }
  // Its parts, or without parts one unnamed skinned part over the whole model (a saver names
  // that mesh after the model).
  std::vector<MeshPart> meshes() const;
  // Empty when every invariant above holds; otherwise the first violation, in words.
  std::string validate() const;
};

// Area-weighted smooth vertex normals of the triangle mesh (unit length; +Y where undefined).
std::vector<glm::vec3> compute_vertex_normals(const std::vector<glm::vec3>& positions,
                                              const std::vector<std::uint32_t>& indices);

}  // namespace sweepd::deform
