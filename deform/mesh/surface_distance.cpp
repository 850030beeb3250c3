#include "deform/mesh/surface_distance.h"

#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace sweepd::deform {

std::vector<float> distance_along_edges(const VertexAdjacency& adjacency,
                                        const std::vector<bool>& is_source) {
  if (is_source.size() != adjacency.vertex_count())
    throw std::invalid_argument("distance_along_edges: one source flag per vertex expected");
  std::vector<float> start(is_source.size(), std::numeric_limits<float>::infinity());
  for (std::size_t v = 0; v < start.size(); ++v)
    if (is_source[v]) start[v] = 0.0f;
  return distance_along_edges(adjacency, start);
}

std::vector<float> distance_along_edges(const VertexAdjacency& adjacency,
                                        std::span<const float> start) {
  const std::size_t n = adjacency.vertex_count();
  if (start.size() != n)
    throw std::invalid_argument("distance_along_edges: one start distance per vertex expected");

  std::vector<float> distance(start.begin(), start.end());
  using Entry = std::pair<float, std::uint32_t>;  // tentative distance, vertex
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::size_t v = 0; v < n; ++v)
    if (distance[v] < std::numeric_limits<float>::infinity())
      queue.push({distance[v], static_cast<std::uint32_t>(v)});
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
