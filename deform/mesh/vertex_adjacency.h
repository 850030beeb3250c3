// Vertex-vertex adjacency of a triangle mesh in compressed rows, with the length of every edge:
// the rings that bind-time walks over the surface read (Dijkstra in surface_distance, the
// smoothing passes of length_weighted_smoothing, the mannequin's relaxation). Built once from
// the triangles; flat arrays, no per-vertex allocation.
//
// Inputs:  positions  #V vertex positions
//          indices    #I triangle corners, #I % 3 == 0, every index < #V
// Output:  VertexAdjacency: for vertex v, neighbours(v) lists every vertex sharing an edge with
//          v, ascending and each once; lengths(v)[i] = |positions[neighbours(v)[i]] -
//          positions[v]|. #V + 1 row starts, 2 × #edges entries.
// Throws std::invalid_argument when #I is not a multiple of 3 or an index is out of range.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

struct VertexAdjacency {
  std::vector<std::uint32_t> row_start;  // #V + 1
  std::vector<std::uint32_t> neighbour;  // row_start[#V] entries
  std::vector<float> edge_length;        // parallel to neighbour

  std::size_t vertex_count() const { return row_start.size() - 1; }
  std::span<const std::uint32_t> neighbours(std::uint32_t v) const {
    return {neighbour.data() + row_start[v], neighbour.data() + row_start[v + 1]};
  }
  std::span<const float> lengths(std::uint32_t v) const {
    return {edge_length.data() + row_start[v], edge_length.data() + row_start[v + 1]};
  }
};

VertexAdjacency vertex_adjacency(std::span<const glm::vec3> positions,
                                 std::span<const std::uint32_t> indices);

}  // namespace sweepd::deform
