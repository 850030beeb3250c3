// CPU references for UV-space rasterisation tests: what a position map must hold at a vertex's
// texel (barycentric interpolation of the triangle containing the texel centre) and how many
// texels the UV triangles should cover.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

namespace sweepd::gpu::test_reference {

struct MapView {
  int width, height;
  std::span<const float> positions;  // W*H*3
  std::span<const float> coverage;   // W*H
};

// At each vertex's texel centre c, what the map must hold, found among all UV triangles (a grid
// of buckets finds the candidates):
// - c inside exactly one triangle (farther than kEdgeMargin from its edges): covered, and P the
//   barycentric interpolation there, or that of a triangle whose edge passes within kEdgeMargin
//   of c (where UV charts meet or fold, snapping may put c inside it too, and drawn later it
//   wins);
// - c inside two or more triangles: the UV layout overlaps there (the later triangle wins on
//   the GPU): counted in `overlapping`, not checked;
// - c within kEdgeMargin of edges only: the fill rule and vertex snapping decide coverage;
//   if covered, P must match one of those triangles;
// - c outside every triangle: uncovered.
// Rasterisers snap vertices to a sub-pixel grid (1/256 px on llvmpipe): an edge may move by
// that much, hence kEdgeMargin = 1/128 px, and the interpolation plane may move by about
// |dP/dpx| / 256: the value tolerance allows 1/256 px of the triangle's gradient plus 1e-6
// relative for float32 round-off.
struct VertexCheck {
  int checked = 0;      // vertices whose texel value or coverage was compared
  int overlapping = 0;  // texel centre inside several UV triangles
  int covered_mismatch = 0;
  int value_mismatch = 0;
  double worst_error_over_tolerance = 0.0;
  std::vector<std::string> mismatches;  // the first few, in words, for failure messages
};

inline VertexCheck check_vertex_texels(std::span<const glm::vec2> uvs,
                                       std::span<const glm::vec3> values,
                                       std::span<const std::uint32_t> indices, const MapView& map) {
  constexpr double kEdgeMargin = 1.0 / 128.0;
  constexpr int kCell = 8;  // texels per bucket side
  const glm::dvec2 size(map.width, map.height);
  const int columns = (map.width + kCell - 1) / kCell, rows = (map.height + kCell - 1) / kCell;
  std::vector<std::vector<std::uint32_t>> buckets(static_cast<std::size_t>(columns) * rows);
  for (std::uint32_t t = 0; t < indices.size() / 3; ++t) {
    glm::dvec2 low(1e30), high(-1e30);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 p = glm::dvec2(uvs[indices[3 * t + k]]) * size;
      low = glm::min(low, p);
      high = glm::max(high, p);
    }
    const glm::ivec2 from = glm::clamp(glm::ivec2(glm::floor(low / double(kCell))), glm::ivec2(0),
                                       glm::ivec2(columns - 1, rows - 1));
    const glm::ivec2 to = glm::clamp(glm::ivec2(glm::floor(high / double(kCell))), glm::ivec2(0),
                                     glm::ivec2(columns - 1, rows - 1));
    for (int y = from.y; y <= to.y; ++y)
      for (int x = from.x; x <= to.x; ++x) buckets[y * columns + x].push_back(t);
  }
  VertexCheck result;
  auto note = [&](std::string what, std::size_t vertex, glm::dvec2 texel) {
    if (result.mismatches.size() < 10) {
      result.mismatches.push_back(what + " at vertex " + std::to_string(vertex) + ", texel " +
                                  std::to_string(int(texel.x)) + "," +
                                  std::to_string(int(texel.y)));
    }
  };
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const glm::dvec2 texel = glm::floor(glm::dvec2(uvs[i]) * size);
    if (texel.x < 0 || texel.y < 0 || texel.x >= size.x || texel.y >= size.y) continue;
    const glm::dvec2 centre = texel + 0.5;
    struct Hit {
      glm::dvec3 expected;
      double tolerance;
    };
    std::vector<Hit> inside, on_edge;
    const auto& bucket = buckets[int(texel.y) / kCell * columns + int(texel.x) / kCell];
    for (std::uint32_t t : bucket) {
      glm::dvec2 p[3];
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec2(uvs[indices[3 * t + k]]) * size;
        v[k] = glm::dvec3(values[indices[3 * t + k]]);
      }
      const glm::dmat2 edges(p[1] - p[0], p[2] - p[0]);
      const double det = glm::determinant(edges);
      if (std::abs(det) < 1e-12) continue;
      // Signed distance (px) from the centre to each edge, positive inside.
      double distance = 1e30;
      for (int k = 0; k < 3; ++k) {
        const glm::dvec2 a = p[k], b = p[(k + 1) % 3], e = b - a, w = centre - a;
        const double cross = (e.x * w.y - e.y * w.x) * (det > 0 ? 1.0 : -1.0);
        distance = std::min(distance, cross / glm::length(e));
      }
      if (distance < -kEdgeMargin) continue;
      const glm::dmat2 inverse = glm::inverse(edges);
      const glm::dvec2 b = inverse * (centre - p[0]);
      const glm::dvec3 d1 = v[1] - v[0], d2 = v[2] - v[0];
      const glm::dvec3 expected = v[0] + b.x * d1 + b.y * d2;
      // Gradient of the interpolated values per pixel along x and along y.
      const glm::dvec3 per_x = d1 * inverse[0][0] + d2 * inverse[0][1];
      const glm::dvec3 per_y = d1 * inverse[1][0] + d2 * inverse[1][1];
      const double tolerance =
          1e-6 * (glm::length(expected) + 1.0) + (glm::length(per_x) + glm::length(per_y)) / 256.0;
      (distance > kEdgeMargin ? inside : on_edge).push_back({expected, tolerance});
    }
    if (inside.size() > 1) {
      ++result.overlapping;
      continue;
    }
    const std::size_t at =
        static_cast<std::size_t>(texel.y) * map.width + static_cast<std::size_t>(texel.x);
    const bool covered = map.coverage[at] == 1.0f;
    ++result.checked;
    if (inside.empty() && on_edge.empty()) {
      if (covered) {
        ++result.covered_mismatch;
        note("covered outside every triangle", i, texel);
      }
      continue;
    }
    if (inside.size() == 1) {
      if (!covered) {
        ++result.covered_mismatch;
        note("uncovered inside a triangle", i, texel);
        continue;
      }
      on_edge.push_back(inside.front());  // the value must match this one or an edge's
    }
    if (!covered) continue;  // on an edge only: the fill rule decides
    const glm::dvec3 got(map.positions[3 * at], map.positions[3 * at + 1],
                         map.positions[3 * at + 2]);
    double best = 1e30;
    for (const Hit& hit : on_edge)
      best = std::min(best, glm::length(got - hit.expected) / hit.tolerance);
    result.worst_error_over_tolerance = std::max(result.worst_error_over_tolerance, best);
    if (best > 1.0) {
      ++result.value_mismatch;
      note("value off by " + std::to_string(best) + " tolerances", i, texel);
    }
  }
  return result;
}

// Covered texels expected from the UV triangles' area, and the allowed difference: sampling at
// texel centres gains or loses at most half a texel per texel of island border crossed, plus
// one texel per border edge for its end points. Assumes UV triangles do not overlap.
struct CoverageExpectation {
  double texels;
  double tolerance;
};

inline CoverageExpectation expected_coverage(std::span<const glm::vec2> uvs,
                                             std::span<const std::uint32_t> indices, int width,
                                             int height) {
  const glm::dvec2 size(width, height);
  double area = 0.0;
  std::vector<std::pair<std::uint64_t, int>> edges;  // undirected edge key, use count
  for (std::size_t t = 0; t < indices.size() / 3; ++t) {
    const glm::dvec2 a = glm::dvec2(uvs[indices[3 * t]]) * size;
    const glm::dvec2 b = glm::dvec2(uvs[indices[3 * t + 1]]) * size;
    const glm::dvec2 c = glm::dvec2(uvs[indices[3 * t + 2]]) * size;
    area += 0.5 * std::abs(glm::determinant(glm::dmat2(b - a, c - a)));
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t i = indices[3 * t + k], j = indices[3 * t + (k + 1) % 3];
      edges.push_back({std::min(i, j) << 32 | std::max(i, j), 1});
    }
  }
  std::sort(edges.begin(), edges.end());
  double border = 0.0;
  int border_edges = 0;
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t end = e;
    while (end < edges.size() && edges[end].first == edges[e].first) ++end;
    if (end - e == 1) {
      const auto i = static_cast<std::uint32_t>(edges[e].first >> 32);
      const auto j = static_cast<std::uint32_t>(edges[e].first & 0xffffffffu);
      border += glm::length((glm::dvec2(uvs[i]) - glm::dvec2(uvs[j])) * size);
      ++border_edges;
    }
    e = end;
  }
  return {area, 0.5 * border + border_edges};
}

}  // namespace sweepd::gpu::test_reference
