// Shortest-edge decimation: reduces a closed 2-manifold triangle mesh to a target vertex count
// by collapsing its shortest edges first, keeping it a 2-manifold (OpenMesh's link condition)
// and refusing collapses that would flip a triangle. Each collapse puts the surviving vertex
// at place(midpoint), e.g. the midpoint projected back onto an implicit surface.
// Deterministic: ties between equal lengths go to the lower edge index.
//
// Inputs:  positions  #V vertex positions (no two equal), indices #F*3 triangles
//          target_vertices  stop once this many vertices are left (or no collapse is allowed)
//          place  where the surviving vertex of a collapse goes, given the edge midpoint
// Outputs: positions, indices  replaced by the decimated mesh (vertices renumbered densely)
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

namespace sweepd::mannequin {

void decimate_shortest_edges(std::vector<glm::vec3>& positions, std::vector<std::uint32_t>& indices,
                             std::size_t target_vertices,
                             const std::function<glm::vec3(const glm::vec3&)>& place);

}  // namespace sweepd::mannequin
