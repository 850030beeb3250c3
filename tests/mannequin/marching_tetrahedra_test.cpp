// Tests of marching_tetrahedra on fields whose surfaces are known exactly.
#include "mannequin/marching_tetrahedra.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "deform/mesh/mesh_topology.h"

namespace sweepd::mannequin {

using namespace deform;  // the mannequin is made of the deform library's types
namespace {

BlockField whole_field(float (*f)(const glm::vec3&)) {
  return [f](const glm::vec3&, const glm::vec3&, std::span<const glm::vec3> points,
             std::span<float> values) {
    for (std::size_t i = 0; i < points.size(); ++i) values[i] = f(points[i]);
    return true;
  };
}

const glm::vec3 kCentre(0.013f, -0.021f, 0.007f);  // off the grid points on purpose
constexpr float kRadius = 0.5f;

float sphere(const glm::vec3& p) { return glm::length(p - kCentre) - kRadius; }

SampleGrid grid_around_origin(float half_size, float spacing) {
  SampleGrid grid;
  grid.spacing = spacing;
  grid.origin = glm::vec3(-half_size);
  grid.cells = glm::ivec3(static_cast<int>(std::round(2.0f * half_size / spacing)));
  return grid;
}

double enclosed_volume(const IsoSurface& surface) {
  double six_volume = 0.0;
  for (std::size_t t = 0; t < surface.indices.size(); t += 3)
    six_volume += glm::dot(glm::dvec3(surface.positions[surface.indices[t]]),
                           glm::cross(glm::dvec3(surface.positions[surface.indices[t + 1]]),
                                      glm::dvec3(surface.positions[surface.indices[t + 2]])));
  return six_volume / 6.0;
}

TEST(MarchingTetrahedra, SphereIsClosedOutwardAndOnTheSurface) {
  IsoSurface surface;
  const SampleGrid grid = grid_around_origin(0.7f, 0.05f);
  marching_tetrahedra(grid, whole_field(sphere), surface);
  const MeshTopology topology = analyze_topology(surface.positions, surface.indices);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.euler_characteristic, 2);
  EXPECT_EQ(topology.welded_vertices, surface.positions.size());  // no two vertices coincide
  float worst = 0.0f;
  for (const glm::vec3& p : surface.positions) worst = std::max(worst, std::abs(sphere(p)));
  // Linear interpolation along edges up to sqrt(3) * 5 cm long on a 0.5 m sphere: the chord
  // sag is below L^2 / (8 R) = 1.9 mm.
  EXPECT_LT(worst, 0.002f);
  const double exact = 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;
  EXPECT_NEAR(enclosed_volume(surface), exact, 0.01 * exact);  // positive: faces point out
}

TEST(MarchingTetrahedra, SkippedEmptyBlocksGiveTheSameMesh) {
  IsoSurface full, culled;
  const SampleGrid grid = grid_around_origin(1.2f, 0.05f);
  marching_tetrahedra(grid, whole_field(sphere), full);
  std::size_t skipped = 0;
  marching_tetrahedra(
      grid,
      [&skipped](const glm::vec3& lo, const glm::vec3& hi, std::span<const glm::vec3> points,
                 std::span<float> values) {
        const glm::vec3 nearest = glm::clamp(kCentre, lo, hi);
        if (glm::length(nearest - kCentre) > kRadius + 0.01f) {
          ++skipped;
          return false;
        }
        for (std::size_t i = 0; i < points.size(); ++i) values[i] = sphere(points[i]);
        return true;
      },
      culled);
  EXPECT_GT(skipped, 0u);
  EXPECT_EQ(culled.indices, full.indices);
  EXPECT_EQ(culled.positions, full.positions);
}

float torus(const glm::vec3& p) {
  const glm::vec2 q(glm::length(glm::vec2(p.x, p.z)) - 0.5f, p.y);
  return glm::length(q) - 0.2f;
}

TEST(MarchingTetrahedra, TorusHasGenusOne) {
  IsoSurface surface;
  marching_tetrahedra(grid_around_origin(0.8f, 0.04f), whole_field(torus), surface);
  const MeshTopology topology = analyze_topology(surface.positions, surface.indices);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.euler_characteristic, 0);  // 2 - 2 * genus
}

// A cube whose faces lie exactly on grid planes: many samples are exactly 0.
float grid_aligned_cube(const glm::vec3& p) {
  const glm::vec3 d = glm::abs(p) - glm::vec3(0.5f);
  return std::max({d.x, d.y, d.z});
}

TEST(MarchingTetrahedra, SamplesExactlyZeroStillGiveAClosedManifold) {
  IsoSurface surface;
  marching_tetrahedra(grid_around_origin(1.0f, 0.25f), whole_field(grid_aligned_cube), surface);
  const MeshTopology topology = analyze_topology(surface.positions, surface.indices);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.euler_characteristic, 2);
  EXPECT_EQ(topology.welded_vertices, surface.positions.size());
}

TEST(MarchingTetrahedra, GridEntirelyInsideGivesNoTriangles) {
  IsoSurface surface;
  surface.positions.push_back(glm::vec3(1.0f));  // stale content is replaced
  marching_tetrahedra(grid_around_origin(0.2f, 0.1f), whole_field(sphere), surface);
  EXPECT_TRUE(surface.positions.empty());
  EXPECT_TRUE(surface.indices.empty());
}

}  // namespace
}  // namespace sweepd::mannequin
