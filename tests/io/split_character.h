// A character made of several meshes, cut mechanically from a single-mesh one (issue 15,
// item 6): split_character(original) cuts it into three skinned meshes on its skin — legs below
// the hips, head above the neck's base, and a torso mesh of two primitives (left and right of
// x = 0, materials "shirt_left" and "shirt_right") — and adds "hat", a closed octahedron of
// half-size 5 cm, 12 cm above the Head joint, parented rigidly to it.
// Each piece holds its triangles in their original order and the vertices they use in
// ascending original order, so a vertex on a cut appears in every piece that meets there.
// Output: SplitCharacter: model (Model::parts: legs, torso, torso, head, hat; meshes 0, 1, 1,
//         2, 3) and source (per vertex: the original vertex it copies, -1 for the hat's 6).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::io::testing {

// The split character and, per vertex, the original vertex it copies (-1: the prop's).
struct SplitCharacter {
  deform::Model model;
  std::vector<int> source;
};

// Which piece a triangle goes to, by its centroid: legs below the hips, the head above the
// neck's base, the torso (two primitives: left and right of x = 0) in between.
enum Piece { kLegs = 0, kTorsoLeft = 1, kTorsoRight = 2, kHead = 3 };
inline Piece piece_of(const deform::Model& model, std::size_t triangle) {
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  const float hips = world[model.skeleton.find("Hips")][3].y;
  const float neck = world[model.skeleton.find("Neck")][3].y;
  glm::vec3 centre(0.0f);
  for (int k = 0; k < 3; ++k) centre += model.positions[model.indices[3 * triangle + k]] / 3.0f;
  if (centre.y < hips) return kLegs;
  if (centre.y > neck) return kHead;
  return centre.x < 0.0f ? kTorsoLeft : kTorsoRight;
}

// A closed octahedron of half-size 5 cm, 12 cm above the head joint: it touches nothing.
inline void add_prop(SplitCharacter& split, int head) {
  deform::Model& model = split.model;
  const glm::vec3 centre =
      glm::vec3(model.skeleton.world_rest_matrices()[head][3]) + glm::vec3(0, 0.12f, 0);
  const glm::vec3 corners[6] = {{0.05f, 0, 0},  {-0.05f, 0, 0}, {0, 0.05f, 0},
                                {0, -0.05f, 0}, {0, 0, 0.05f},  {0, 0, -0.05f}};
  const std::uint32_t faces[24] = {0, 2, 4, 4, 2, 1, 1, 2, 5, 5, 2, 0,
                                   4, 3, 0, 1, 3, 4, 5, 3, 1, 0, 3, 5};
  deform::MeshPart part{.name = "hat",
                        .material = "felt",
                        .mesh = 3,
                        .first_vertex = static_cast<std::uint32_t>(model.vertex_count()),
                        .vertex_count = 6,
                        .first_index = static_cast<std::uint32_t>(model.indices.size()),
                        .index_count = 24,
                        .rigid_joint = head};
  for (const glm::vec3& corner : corners) {
    model.positions.push_back(centre + corner);
    model.normals.push_back(glm::normalize(corner));
    if (model.has_uvs()) model.uvs.emplace_back(0.5f, 0.5f);
    model.skin_joints.push_back({static_cast<std::uint16_t>(head), 0, 0, 0});
    model.skin_weights.push_back({1.0f, 0.0f, 0.0f, 0.0f});
    split.source.push_back(-1);
  }
  for (std::uint32_t corner : faces) model.indices.push_back(part.first_vertex + corner);
  model.parts.push_back(part);
}

// The original cut into legs, torso (two primitives) and head — each piece's triangles in their
// original order, its vertices the ones they use in ascending original order, so the seams'
// vertices appear in every piece that meets there — plus the hat.
inline SplitCharacter split_character(const deform::Model& original) {
  SplitCharacter split;
  deform::Model& model = split.model;
  model.name = original.name + "_split";
  model.skeleton = original.skeleton;
  const char* names[4] = {"legs", "torso", "torso", "head"};
  const char* materials[4] = {"skin", "shirt_left", "shirt_right", "skin"};
  const std::uint32_t meshes[4] = {0, 1, 1, 2};
  for (int piece = kLegs; piece <= kHead; ++piece) {
    std::vector<int> index_of(original.vertex_count(), -1);
    std::vector<std::uint32_t> triangles;
    for (std::size_t t = 0; t < original.triangle_count(); ++t)
      if (piece_of(original, t) == piece)
        for (int k = 0; k < 3; ++k) {
          index_of[original.indices[3 * t + k]] = 0;
          triangles.push_back(original.indices[3 * t + k]);
        }
    deform::MeshPart part{.name = names[piece],
                          .material = materials[piece],
                          .mesh = meshes[piece],
                          .first_vertex = static_cast<std::uint32_t>(model.vertex_count()),
                          .first_index = static_cast<std::uint32_t>(model.indices.size())};
    for (std::size_t v = 0; v < original.vertex_count(); ++v) {
      if (index_of[v] < 0) continue;
      index_of[v] = static_cast<int>(model.vertex_count());
      split.source.push_back(static_cast<int>(v));
      model.positions.push_back(original.positions[v]);
      model.normals.push_back(original.normals[v]);
      if (original.has_uvs()) model.uvs.push_back(original.uvs[v]);
      model.skin_joints.push_back(original.skin_joints[v]);
      model.skin_weights.push_back(original.skin_weights[v]);
    }
    for (std::uint32_t corner : triangles) model.indices.push_back(index_of[corner]);
    part.vertex_count = static_cast<std::uint32_t>(model.vertex_count()) - part.first_vertex;
    part.index_count = static_cast<std::uint32_t>(model.indices.size()) - part.first_index;
    model.parts.push_back(part);
  }
  add_prop(split, original.skeleton.find("Head"));
  return split;
}

}  // namespace sweepd::io::testing
