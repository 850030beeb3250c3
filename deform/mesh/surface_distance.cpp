#include "deform/mesh/surface_distance.h"

#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace sweepd::deform {

std::vector<float> distance_along_edges(std::span<const glm::vec3> positions,
                                        std::span<const std::uint32_t> indices,
                                        const std::vector<bool>& is_source) {
  const std::size_t n = positions.size();
  if (is_source.size() != n)
    throw std::invalid_argument("distance_along_edges: one source flag per vertex expected");
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("distance_along_edges: indices are not whole triangles");
  std::vector<std::vector<std::uint32_t>> neighbours(n);
  for (std::size_t t = 0; t < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      if (a >= n || b >= n)
        throw std::invalid_argument("distance_along_edges: vertex index out of range");
      neighbours[a].push_back(b);
      neighbours[b].push_back(a);
    }

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
    for (std::uint32_t u : neighbours[v]) {
      const float through_v = d + glm::length(positions[u] - positions[v]);
      if (through_v < distance[u]) {
        distance[u] = through_v;
        queue.push({through_v, u});
      }
    }
  }
  return distance;
}

}  // namespace sweepd::deform
