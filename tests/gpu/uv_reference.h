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
#include <vector>

namespace sweepd::gpu::test_reference {

struct MapView {
  int width, height;
  std::span<const float> positions;  // W*H*3
  std::span<const float> coverage;   // W*H
};

// Vertex i's texel centre, and the values interpolated there in a triangle of i's fan that
// contains it. Rasterisers snap vertices to a sub-pixel grid (1/256 px on llvmpipe), which can
// move the interpolation plane by about |dP/dpx| / 256: the tolerance allows 1/256 px of the
// triangle's gradient, plus 1e-6 relative for float32 round-off.
struct VertexCheck {
  int checked = 0;  // vertices whose texel centre lies inside a triangle of their own fan
  int covered_mismatch = 0;
  int value_mismatch = 0;
  double worst_error_over_tolerance = 0.0;
};

inline VertexCheck check_vertex_texels(std::span<const glm::vec2> uvs,
                                       std::span<const glm::vec3> values,
                                       std::span<const std::uint32_t> indices, const MapView& map) {
  std::vector<std::vector<std::uint32_t>> fans(uvs.size());
  for (std::uint32_t t = 0; t < indices.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) fans[indices[3 * t + k]].push_back(t);
  const glm::dvec2 size(map.width, map.height);
  VertexCheck result;
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    const glm::dvec2 texel = glm::floor(glm::dvec2(uvs[i]) * size);
    if (texel.x < 0 || texel.y < 0 || texel.x >= size.x || texel.y >= size.y) continue;
    const glm::dvec2 centre = texel + 0.5;
    for (std::uint32_t t : fans[i]) {
      glm::dvec2 p[3];
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k) {
        p[k] = glm::dvec2(uvs[indices[3 * t + k]]) * size;
        v[k] = glm::dvec3(values[indices[3 * t + k]]);
      }
      const glm::dmat2 edges(p[1] - p[0], p[2] - p[0]);
      const double det = glm::determinant(edges);
      if (std::abs(det) < 1e-9) continue;
      const glm::dvec2 b = glm::inverse(edges) * (centre - p[0]);
      const double inside_margin = 1e-6;  // texel centres on a shared edge count for both sides
      if (b.x < -inside_margin || b.y < -inside_margin || b.x + b.y > 1.0 + inside_margin) continue;
      const glm::dvec3 expected = v[0] + b.x * (v[1] - v[0]) + b.y * (v[2] - v[0]);
      // Gradient of the interpolated values per pixel along x and along y.
      const glm::dmat2 inverse = glm::inverse(edges);
      const glm::dvec3 d1 = v[1] - v[0], d2 = v[2] - v[0];
      const glm::dvec3 per_x = d1 * inverse[0][0] + d2 * inverse[0][1];
      const glm::dvec3 per_y = d1 * inverse[1][0] + d2 * inverse[1][1];
      const double tolerance =
          1e-6 * (glm::length(expected) + 1.0) + (glm::length(per_x) + glm::length(per_y)) / 256.0;
      const std::size_t at =
          static_cast<std::size_t>(texel.y) * map.width + static_cast<std::size_t>(texel.x);
      ++result.checked;
      if (map.coverage[at] != 1.0f) {
        ++result.covered_mismatch;
      } else {
        const glm::dvec3 got(map.positions[3 * at], map.positions[3 * at + 1],
                             map.positions[3 * at + 2]);
        const double error = glm::length(got - expected);
        result.worst_error_over_tolerance =
            std::max(result.worst_error_over_tolerance, error / tolerance);
        if (error > tolerance) ++result.value_mismatch;
      }
      break;
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
