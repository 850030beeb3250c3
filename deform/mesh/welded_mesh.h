// The welded mesh a bind works on: a model's triangles with its UV-seam copies merged into one
// vertex per distinct position (weld_coincident_positions, mesh_topology.h), with the welded
// vertices' adjacency. Built once per bind and read by every bind-time stage that walks the
// surface: the cross-section cuts, the blending shares and their smoothing, the neck's surface
// ramp, the shoulders' skinned-share smoothing.
//
// Inputs:  positions  #P model vertex positions (seam copies allowed)
//          indices    #I triangle corners, #I % 3 == 0, every index < #P
// Output:  WeldedMesh: welded_id (#P, dense ids in first-seen order), positions (#W, each
//          welded vertex at its model position), indices (#I, the same triangles on welded
//          ids), adjacency (#W rows, vertex_adjacency.h).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/mesh/vertex_adjacency.h"

namespace sweepd::deform {

struct WeldedMesh {
  std::vector<std::uint32_t> welded_id;
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
  VertexAdjacency adjacency;

  std::size_t vertex_count() const { return positions.size(); }
};

WeldedMesh weld_mesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);

}  // namespace sweepd::deform
