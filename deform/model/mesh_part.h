// MeshPart: one mesh of a character that a file holds as several (glTF: one per triangle
// primitive of every skinned mesh on the character's skin, and of every mesh parented rigidly to
// one of its joints) — which of the Model's vertices and triangles came from it, what it is
// called, and how it moves. Plain data: loaders fill it, the binding reads which parts join the
// body's sweeps (deform/binding/mesh_parts_joined.h), savers and the protocol pass it on.
//
// A Model with no parts is one mesh. Parts, when present, follow each other without gaps:
// part k's vertices are [first_vertex, first_vertex + vertex_count) and its triangle corners
// [first_index, first_index + index_count) of Model::indices, each corner inside the part's own
// vertex range (Model::validate checks it).
#pragma once

#include <cstdint>
#include <string>

namespace sweepd::deform {

struct MeshPart {
  std::string name;      // the file's mesh name (else its node's, else "mesh_<index>")
  std::string material;  // the material's name; empty when the file gives none
  // Which of the file's mesh nodes it came from, 0-based in file order: the parts of one mesh
  // (its primitives, in order) share it.
  std::uint32_t mesh = 0;
  std::uint32_t first_vertex = 0, vertex_count = 0;
  std::uint32_t first_index = 0, index_count = 0;
  // >= 0: the file's mesh had no skin and hangs under this joint; its vertices have weight 1 on
  // it and follow it rigidly. -1: skinned.
  int rigid_joint = -1;

  bool operator==(const MeshPart&) const = default;
};

}  // namespace sweepd::deform
