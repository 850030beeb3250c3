// The exact triangle–triangle test: crossing, near misses, touching, coplanar cases, degenerate
// triangles, and agreement with an independent edge-against-triangle reference on random pairs.
#include "deform/features/triangle_intersection.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace sweepd::deform {
namespace {

using Triangle = std::array<glm::vec3, 3>;

const Triangle kFloor = {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)};

bool intersect(const Triangle& a, const Triangle& b) { return triangles_intersect(a, b); }

Triangle moved(const Triangle& t, glm::vec3 by) { return {t[0] + by, t[1] + by, t[2] + by}; }

// The answer must not depend on which triangle comes first or which corner starts.
void expect_symmetric(const Triangle& a, const Triangle& b, bool expected) {
  const Triangle a_rotated = {a[1], a[2], a[0]}, b_flipped = {b[0], b[2], b[1]};
  EXPECT_EQ(intersect(a, b), expected);
  EXPECT_EQ(intersect(b, a), expected);
  EXPECT_EQ(intersect(a_rotated, b_flipped), expected);
  EXPECT_EQ(intersect(b_flipped, a_rotated), expected);
}

TEST(TriangleIntersection, CrossingTrianglesIntersect) {
  // In the plane x = 0.25, crossing the floor along y in [0.1, 0.75].
  const Triangle wall = {glm::vec3(0.25f, 0.1f, -1), glm::vec3(0.25f, 0.1f, 1),
                         glm::vec3(0.25f, 2, 0)};
  expect_symmetric(kFloor, wall, true);
}

TEST(TriangleIntersection, WallPastTheHypotenuseMisses) {
  // Same wall at x = 0.95: the floor there has y <= 0.05, the wall starts at y = 0.1.
  const Triangle wall = {glm::vec3(0.95f, 0.1f, -1), glm::vec3(0.95f, 0.1f, 1),
                         glm::vec3(0.95f, 2, 0)};
  expect_symmetric(kFloor, wall, false);
}

TEST(TriangleIntersection, PiercingThroughTheInteriorIntersects) {
  // A thin spike whose tip passes through the floor's interior; no edge of the floor is hit.
  const Triangle spike = {glm::vec3(0.3f, 0.3f, -0.5f), glm::vec3(0.31f, 0.3f, 0.5f),
                          glm::vec3(0.3f, 0.31f, 0.5f)};
  expect_symmetric(kFloor, spike, true);
}

TEST(TriangleIntersection, ParallelNearMissDoesNotIntersect) {
  // 1 µm above the floor: a near miss must stay a miss.
  expect_symmetric(kFloor, moved(kFloor, {0, 0, 1e-6f}), false);
  expect_symmetric(kFloor, moved(kFloor, {0.1f, 0.1f, -1e-6f}), false);
}

TEST(TriangleIntersection, TouchingAtAVertexOrEdgeCountsAsIntersecting) {
  // Closed triangles: a shared corner point or a shared edge segment is a common point.
  const Triangle corner_up = {glm::vec3(1, 0, 0), glm::vec3(2, 0, 1), glm::vec3(2, 1, 1)};
  expect_symmetric(kFloor, corner_up, true);
  const Triangle edge_up = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(1, 1, 1)};
  expect_symmetric(kFloor, edge_up, true);
  // Touching the floor's interior with one corner from above.
  const Triangle tip_down = {glm::vec3(0.2f, 0.2f, 0), glm::vec3(0.2f, 0.5f, 1),
                             glm::vec3(0.5f, 0.2f, 1)};
  expect_symmetric(kFloor, tip_down, true);
}

TEST(TriangleIntersection, CoplanarCases) {
  expect_symmetric(kFloor, moved(kFloor, {0.2f, 0.2f, 0}), true);   // overlapping
  expect_symmetric(kFloor, moved(kFloor, {1.5f, 0.0f, 0}), false);  // apart
  // Entirely inside the floor: no edges cross, the vertex-in-triangle test decides.
  const Triangle inner = {glm::vec3(0.1f, 0.1f, 0), glm::vec3(0.3f, 0.1f, 0),
                          glm::vec3(0.1f, 0.3f, 0)};
  expect_symmetric(kFloor, inner, true);
  // Mirror image across the hypotenuse: shares only that edge (touching, so true) ...
  const Triangle mirror = {glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(0, 1, 0)};
  expect_symmetric(kFloor, mirror, true);
  // ... and pushed away from it by 1e-3, apart.
  expect_symmetric(kFloor, moved(mirror, {1e-3f, 1e-3f, 0}), false);
}

TEST(TriangleIntersection, DegenerateTrianglesIntersectNothing) {
  const Triangle needle = {glm::vec3(0.2f, 0.2f, -1), glm::vec3(0.2f, 0.2f, 1),
                           glm::vec3(0.2f, 0.2f, 0)};
  expect_symmetric(kFloor, needle, false);
}

// Independent reference for triangles in general position: they meet iff an edge of one
// crosses the other (Möller–Trumbore on segments, in double).
bool segment_hits_triangle(glm::dvec3 p, glm::dvec3 q, const Triangle& t) {
  const glm::dvec3 a(t[0]), b(t[1]), c(t[2]);
  const glm::dvec3 d = q - p, e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
  const double det = glm::dot(e1, h);
  if (std::abs(det) < 1e-300) return false;
  const glm::dvec3 s = p - a;
  const double u = glm::dot(s, h) / det;
  const glm::dvec3 qv = glm::cross(s, e1);
  const double v = glm::dot(d, qv) / det, w = glm::dot(e2, qv) / det;
  return u >= 0 && v >= 0 && u + v <= 1 && w >= 0 && w <= 1;
}

bool reference_intersect(const Triangle& a, const Triangle& b) {
  for (int i = 0; i < 3; ++i) {
    if (segment_hits_triangle(glm::dvec3(a[i]), glm::dvec3(a[(i + 1) % 3]), b)) return true;
    if (segment_hits_triangle(glm::dvec3(b[i]), glm::dvec3(b[(i + 1) % 3]), a)) return true;
  }
  return false;
}

TEST(TriangleIntersection, AgreesWithEdgeReferenceOnRandomPairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  int hits = 0;
  const int trials = 20000;
  for (int n = 0; n < trials; ++n) {
    Triangle a, b;
    for (auto& p : a) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
    for (auto& p : b) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
    const bool expected = reference_intersect(a, b);
    hits += expected;
    ASSERT_EQ(intersect(a, b), expected) << "trial " << n;
  }
  // Both outcomes must be well represented, or the comparison proves little.
  EXPECT_GT(hits, trials / 20);
  EXPECT_LT(hits, trials - trials / 20);
}

}  // namespace
}  // namespace sweepd::deform
