#include "deform/mesh/surface_distance.h"

#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace sweepd::deform {

std::vector<float> distance_along_edges(const VertexAdjacency& adjacency,
                                        const std::vector<bool>& is_source) {
  const std::size_t n = adjacency.vertex_count();
  if (is_source.size() != n)
    throw std::invalid_argument("distance_along_edges: one source flag per vertex expected");

  std::vector<float> distance(n, std::numeric_limits<float>::infinity());
  using Entry = std::pair<float, std::uint32_t>;  // tentative distance, vertex
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t v = 0; v < n; ++v)
    if (is_source[v]) {
      distance[v] = 0.0f;
      queue.push({0.0f, static_cast<std::uint32_t>(v)});
    }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;  // a shorter path reached v already
    const std::span<const std::uint32_t> neighbours = adjacency.neighbours(v);
    const std::span<const float> lengths = adjacency.lengths(v);
    for (std::size_t i = 0; i < neighbours.size(); ++i) {
      const std::uint32_t u = neighbours[i];
      const float through_v = d + lengths[i];
      if (through_v < distance[u]) {
        distance[u] = through_v;
        queue.push({through_v, u});
      }
    }
  }
  return distance;
}

}  // namespace sweepd::deform
