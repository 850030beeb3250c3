#include "deform/mesh/vertex_adjacency.h"

#include <algorithm>
#include <stdexcept>

namespace sweepd::deform {

VertexAdjacency vertex_adjacency(std::span<const glm::vec3> positions,
                                 std::span<const std::uint32_t> indices) {
  const std::size_t n = positions.size();
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("vertex_adjacency: indices are not whole triangles");
  for (std::uint32_t i : indices)
    if (i >= n) throw std::invalid_argument("vertex_adjacency: vertex index out of range");

  // Both directions of every triangle edge, bucketed by their first vertex, then each row
  // sorted and its repeats dropped (an inner edge appears once per triangle on either side).
  VertexAdjacency adjacency;
  std::vector<std::uint32_t> count(n + 1, 0);
  for (std::size_t t = 0; t < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      ++count[indices[t + k] + 1];
      ++count[indices[t + (k + 1) % 3] + 1];
    }
  for (std::size_t v = 0; v < n; ++v) count[v + 1] += count[v];
  std::vector<std::uint32_t> all(count[n]);
  std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
  for (std::size_t t = 0; t < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      all[fill[a]++] = b;
      all[fill[b]++] = a;
    }
  adjacency.row_start.assign(1, 0);
  adjacency.row_start.reserve(n + 1);
  adjacency.neighbour.reserve(all.size() / 2);
  for (std::size_t v = 0; v < n; ++v) {
    const auto begin = all.begin() + count[v], end = all.begin() + count[v + 1];
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it)
      if (it == begin || *it != *(it - 1)) {
        adjacency.neighbour.push_back(*it);
        adjacency.edge_length.push_back(glm::length(positions[*it] - positions[v]));
      }
    adjacency.row_start.push_back(static_cast<std::uint32_t>(adjacency.neighbour.size()));
  }
  return adjacency;
}

}  // namespace sweepd::deform
