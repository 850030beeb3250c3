// Test geometry: open triangulated tubes (no caps) with circular or elliptic sections, for
// cross-section and key-ellipse fitting tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <numbers>
#include <vector>

namespace sweepd::deform::test_geometry {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

struct Tube {
  glm::vec3 base{0.0f};
  glm::vec3 axis{0, 1, 0};    // unit
  glm::vec3 radial{1, 0, 0};  // unit, orthogonal to axis: direction of radius_1
  float radius_1 = 1.0f;      // along radial
  float radius_2 = 1.0f;      // along cross(axis, radial)
  float length = 1.0f;
  int segments = 64;     // columns around
  int rings = 2;         // at distance length * j / (rings - 1) from base
  double covered = 1.0;  // fraction of the turn; < 1 leaves a slot (an open mesh)
};

// Appends the tube's vertices and triangles (two per quad, split along one diagonal).
inline void add_tube(Mesh& mesh, const Tube& tube) {
  const glm::vec3 e1 = tube.radial, e2 = glm::cross(tube.axis, tube.radial);
  const bool closed = tube.covered >= 1.0;
  const int columns = closed ? tube.segments : tube.segments + 1;
  const auto first = static_cast<std::uint32_t>(mesh.positions.size());
  for (int j = 0; j < tube.rings; ++j)
    for (int k = 0; k < columns; ++k) {
      const double angle = 2.0 * std::numbers::pi * tube.covered * k / tube.segments;
      mesh.positions.push_back(
          tube.base + tube.axis * (tube.length * static_cast<float>(j) / (tube.rings - 1)) +
          tube.radius_1 * static_cast<float>(std::cos(angle)) * e1 +
          tube.radius_2 * static_cast<float>(std::sin(angle)) * e2);
    }
  auto at = [&](int j, int k) {
    return first + static_cast<std::uint32_t>(j * columns + k % columns);
  };
  for (int j = 0; j + 1 < tube.rings; ++j)
    for (int k = 0; k < tube.segments; ++k)
      mesh.indices.insert(mesh.indices.end(), {at(j, k), at(j, k + 1), at(j + 1, k + 1), at(j, k),
                                               at(j + 1, k + 1), at(j + 1, k)});
}

}  // namespace sweepd::deform::test_geometry
