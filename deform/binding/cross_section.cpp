#include "deform/binding/cross_section.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace sweepd::deform {
namespace {

// One crossing mesh edge: where the plane cuts it and its (up to two) neighbouring crossings.
struct CrossingNode {
  glm::dvec3 point;
  std::array<int, 2> next{-1, -1};
  int degree() const { return (next[0] >= 0) + (next[1] >= 0); }
};

struct Chain {
  std::vector<glm::dvec3> points;
  bool closed = false;
};

void link_nodes(std::vector<CrossingNode>& nodes, int a, int b) {
  // A third neighbour means a non-manifold edge: it is left out (the chain opens there).
  auto attach = [&](int from, int to) {
    for (int& slot : nodes[from].next)
      if (slot < 0) {
        slot = to;
        return;
      }
  };
  if (nodes[a].degree() < 2 && nodes[b].degree() < 2) {
    attach(a, b);
    attach(b, a);
  }
}

Chain walk_chain(const std::vector<CrossingNode>& nodes, std::vector<bool>& visited, int start) {
  Chain chain;
  int previous = -1, current = start;
  while (current >= 0 && !visited[current]) {
    visited[current] = true;
    const glm::dvec3& p = nodes[current].point;
    if (chain.points.empty() || chain.points.back() != p) chain.points.push_back(p);
    const auto& next = nodes[current].next;
    const int following = next[0] != previous ? next[0] : next[1];
    previous = current;
    current = following;
  }
  chain.closed = current == start;
  if (chain.closed && chain.points.size() > 1 && chain.points.front() == chain.points.back())
    chain.points.pop_back();
  return chain;
}

// Even-odd rule; an open chain is closed by its end-to-start segment.
bool encloses(std::span<const glm::dvec2> polygon, glm::dvec2 q) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const glm::dvec2 a = polygon[i], b = polygon[j];
    if ((a.y > q.y) != (b.y > q.y) && q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x)
      inside = !inside;
  }
  return inside;
}

double polygon_area(std::span<const glm::dvec2> polygon) {
  double twice = 0.0;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++)
    twice += polygon[j].x * polygon[i].y - polygon[i].x * polygon[j].y;
  return 0.5 * std::abs(twice);
}

double distance_to_chain(std::span<const glm::dvec2> polyline, bool closed, glm::dvec2 q) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t segments = closed ? polyline.size() : polyline.size() - 1;
  for (std::size_t i = 0; i < std::max<std::size_t>(segments, 1); ++i) {
    const glm::dvec2 a = polyline[i], b = polyline[(i + 1) % polyline.size()];
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double s = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(q - (a + s * ab)));
  }
  return best;
}

}  // namespace

PlaneFrame make_plane_frame(glm::vec3 origin, glm::vec3 normal, glm::vec3 x_hint) {
  PlaneFrame frame;
  frame.origin = origin;
  frame.normal = glm::normalize(normal);
  glm::vec3 x = x_hint - glm::dot(x_hint, frame.normal) * frame.normal;
  if (glm::length(x) < 1e-4f) {
    const glm::vec3 n = glm::abs(frame.normal);
    const glm::vec3 axis = n.x <= n.y && n.x <= n.z ? glm::vec3(1, 0, 0)
                           : n.y <= n.z             ? glm::vec3(0, 1, 0)
                                                    : glm::vec3(0, 0, 1);
    x = axis - glm::dot(axis, frame.normal) * frame.normal;
  }
  frame.x_axis = glm::normalize(x);
  frame.y_axis = glm::cross(frame.normal, frame.x_axis);
  return frame;
}

CrossSection cross_section(std::span<const glm::vec3> positions,
                           std::span<const std::uint32_t> indices, const PlaneFrame& plane,
                           glm::vec3 link_point) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("cross_section: index count " + std::to_string(indices.size()) +
                                " is not a multiple of 3");
  for (std::uint32_t index : indices)
    if (index >= positions.size())
      throw std::invalid_argument("cross_section: vertex index " + std::to_string(index) +
                                  " out of range (" + std::to_string(positions.size()) +
                                  " vertices)");
  const glm::dvec3 origin(plane.origin), normal(plane.normal);
  auto distance = [&](std::uint32_t v) {
    return glm::dot(glm::dvec3(positions[v]) - origin, normal);
  };

  std::vector<CrossingNode> nodes;
  std::unordered_map<std::uint64_t, int> node_of_edge;
  auto crossing = [&](std::uint32_t u, std::uint32_t v, double du, double dv) {
    if (u > v) {
      std::swap(u, v);
      std::swap(du, dv);
    }
    const std::uint64_t key = (static_cast<std::uint64_t>(u) << 32) | v;
    const auto [it, inserted] = node_of_edge.try_emplace(key, static_cast<int>(nodes.size()));
    if (inserted) {
      // Exactly the vertex when it lies on the plane; otherwise the interpolated point.
      const glm::dvec3 pu(positions[u]), pv(positions[v]);
      const glm::dvec3 point = du == 0.0 ? pu : dv == 0.0 ? pv : pu + (pv - pu) * (du / (du - dv));
      nodes.push_back({point, {-1, -1}});
    }
    return it->second;
  };
  // Each vertex's distance once (a vertex is in about six triangles), and a triangle with its
  // three on one side skipped: the plane crosses few of a body's triangles.
  std::vector<double> distances(positions.size());
  for (std::uint32_t v = 0; v < distances.size(); ++v) distances[v] = distance(v);
  for (std::size_t f = 0; f < indices.size(); f += 3) {
    const std::array<std::uint32_t, 3> v{indices[f], indices[f + 1], indices[f + 2]};
    const std::array<double, 3> d{distances[v[0]], distances[v[1]], distances[v[2]]};
    if ((d[0] >= 0.0) == (d[1] >= 0.0) && (d[1] >= 0.0) == (d[2] >= 0.0)) continue;
    std::array<int, 2> found{};
    int count = 0;
    for (int e = 0; e < 3; ++e) {
      const int g = (e + 1) % 3;
      if ((d[e] >= 0.0) != (d[g] >= 0.0) && count < 2)
        found[count++] = crossing(v[e], v[g], d[e], d[g]);
    }
    if (count == 2) link_nodes(nodes, found[0], found[1]);
  }

  std::vector<Chain> chains;
  std::vector<bool> visited(nodes.size(), false);
  for (int pass = 0; pass < 2; ++pass)  // open chains from their ends first, then closed loops
    for (int i = 0; i < static_cast<int>(nodes.size()); ++i)
      if (!visited[i] && (pass == 1 || nodes[i].degree() < 2))
        chains.push_back(walk_chain(nodes, visited, i));

  CrossSection result;
  result.loop_count = static_cast<int>(chains.size());
  if (chains.empty()) return result;
  auto to_plane = [&](const glm::dvec3& p) {
    const glm::dvec3 d = p - origin;
    return glm::dvec2(glm::dot(d, glm::dvec3(plane.x_axis)), glm::dot(d, glm::dvec3(plane.y_axis)));
  };
  const glm::dvec2 link = to_plane(glm::dvec3(link_point));
  int best = -1;
  double best_score = std::numeric_limits<double>::infinity();
  bool best_encloses = false;
  std::vector<glm::dvec2> flat;
  for (int c = 0; c < static_cast<int>(chains.size()); ++c) {
    flat.clear();
    for (const glm::dvec3& p : chains[c].points) flat.push_back(to_plane(p));
    const bool inside = flat.size() >= 3 && encloses(flat, link);
    // Enclosing loops beat all others; among them the smallest area, else the nearest.
    const double score =
        inside ? polygon_area(flat) : distance_to_chain(flat, chains[c].closed, link);
    if ((inside && !best_encloses) || (inside == best_encloses && score < best_score)) {
      best = c;
      best_score = score;
      best_encloses = inside;
    }
  }
  const Chain& chosen = chains[best];
  result.found = true;
  result.closed = chosen.closed;
  result.encloses_link_point = best_encloses;
  for (const glm::dvec3& p : chosen.points) {
    result.points.push_back(glm::vec3(p));
    result.points_2d.push_back(glm::vec2(to_plane(p)));
  }
  return result;
}

}  // namespace sweepd::deform
