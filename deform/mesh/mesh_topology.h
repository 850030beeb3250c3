// Mesh topology checks: is a triangle soup (as loaded from glTF, with UV-seam duplicates) one
// closed 2-manifold surface once coincident positions are welded? Also converts it into an
// OpenMesh TriMesh for the geometry code that needs connectivity (neighbours, rings, boundaries).
//
// Inputs:  positions  #P  vertex positions (duplicates at UV seams allowed)
//          indices    #I  triangle corners, #I % 3 == 0, every index < #P
// Outputs: MeshTopology (counts below) or TriMesh (welded vertices, one face per accepted triangle)
//
// Welding merges vertices whose positions are exactly equal (no tolerance; -0 equals +0).
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct MeshTopology {
  std::size_t welded_vertices = 0;        // distinct positions referenced by a triangle
  std::size_t unreferenced_vertices = 0;  // distinct positions no triangle uses
  std::size_t triangles = 0;              // non-degenerate triangles after welding
  std::size_t degenerate_triangles = 0;   // triangles with a repeated welded vertex (not counted)
  std::size_t edges = 0;                  // distinct undirected edges
  std::size_t boundary_edges = 0;         // edges with exactly one triangle
  std::size_t non_manifold_edges = 0;     // edges with more than two triangles
  std::size_t non_manifold_vertices = 0;  // vertices whose triangle fan falls apart (bow-tie)
  std::size_t inconsistent_edges = 0;     // two-triangle edges used twice in the same direction
  std::size_t components = 0;             // connected pieces (through shared vertices)
  std::size_t faces_rejected_by_openmesh = 0;  // triangles to_tri_mesh could not add
  long euler_characteristic = 0;               // V - E + F

  // One closed, consistently oriented 2-manifold surface piece per component, nothing dropped.
  bool closed_manifold() const {
    return triangles > 0 && degenerate_triangles == 0 && boundary_edges == 0 &&
           non_manifold_edges == 0 && non_manifold_vertices == 0 && inconsistent_edges == 0 &&
           faces_rejected_by_openmesh == 0;
  }
};

// Welded vertex id of every input vertex (#P entries); ids are dense, in first-seen order.
std::vector<std::uint32_t> weld_coincident_positions(std::span<const glm::vec3> positions,
                                                     std::size_t* welded_count);

MeshTopology analyze_topology(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices);

// OpenMesh mesh of the welded triangles. Triangles OpenMesh rejects (degenerate, or making an
// edge or vertex non-manifold) are left out; *rejected_faces (if given) counts them.
TriMesh to_tri_mesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                    std::size_t* rejected_faces = nullptr);

}  // namespace sweepd::deform
