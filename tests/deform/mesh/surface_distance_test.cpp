// distance_along_edges (and the vertex_adjacency it walks) on small meshes whose shortest edge
// paths are known by hand.
#include "deform/mesh/surface_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace sweepd::deform {
namespace {

// A strip of unit squares along x, two triangles each (diagonals from (i,0) to (i+1,1)), and
// one separate triangle far away. Vertex 2i is (i,0), 2i+1 is (i,1) for i in [0, columns].
struct Strip {
  std::vector<glm::vec3> positions;
  std::vector<std::uint32_t> indices;
};

Strip strip(int columns) {
  Strip s;
  for (int i = 0; i <= columns; ++i) {
    s.positions.push_back({float(i), 0.0f, 0.0f});
    s.positions.push_back({float(i), 1.0f, 0.0f});
  }
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(columns); ++i) {
    const std::uint32_t a = 2 * i, b = 2 * i + 1, c = 2 * i + 2, d = 2 * i + 3;
    s.indices.insert(s.indices.end(), {a, c, d, a, d, b});
  }
  const std::uint32_t first = static_cast<std::uint32_t>(s.positions.size());
  s.positions.insert(s.positions.end(), {{50, 0, 0}, {51, 0, 0}, {50, 1, 0}});
  s.indices.insert(s.indices.end(), {first, first + 1, first + 2});
  return s;
}

TEST(SurfaceDistance, FollowsTheShortestEdgePathFromTheNearestSource) {
  const Strip s = strip(4);
  std::vector<bool> source(s.positions.size(), false);
  source[0] = true;  // (0,0)
  const std::vector<float> d =
      distance_along_edges(vertex_adjacency(s.positions, s.indices), source);
  // Along the bottom row the edges are straight: (i,0) lies i away. (i,1) is reached by the
  // diagonal from (i-1,0), sqrt(2) + (i-1), or by the edge up from (0,0), 1 + i; the top-left
  // corner only by the upward edge. 1e-5: float sums of a few unit lengths.
  for (int i = 0; i <= 4; ++i) {
    EXPECT_NEAR(d[2 * i], float(i), 1e-5f) << "bottom " << i;
    const float top = i == 0 ? 1.0f : std::min(std::sqrt(2.0f) + float(i - 1), 1.0f + float(i));
    EXPECT_NEAR(d[2 * i + 1], top, 1e-5f) << "top " << i;
  }
  // The separate triangle is not reachable.
  for (std::size_t v = s.positions.size() - 3; v < s.positions.size(); ++v)
    EXPECT_TRUE(std::isinf(d[v])) << v;

  // A second source at the far end: each vertex takes the nearer one.
  source[2 * 4] = true;  // (4,0)
  const std::vector<float> both =
      distance_along_edges(vertex_adjacency(s.positions, s.indices), source);
  EXPECT_NEAR(both[2 * 3], 1.0f, 1e-5f);
  EXPECT_NEAR(both[2 * 2], 2.0f, 1e-5f);
  EXPECT_NEAR(both[2 * 4], 0.0f, 0.0f);
}

TEST(SurfaceDistance, FromStartDistancesTakesTheLeastStartPlusPath) {
  const Strip s = strip(4);
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> start(s.positions.size(), inf);
  start[0] = 3.0f;    // (0,0), starting 3 away
  start[2 * 4] = 0.5f;  // (4,0), starting 0.5 away
  const std::vector<float> d = distance_along_edges(vertex_adjacency(s.positions, s.indices), start);
  // Along the bottom row (i,0) is i from (0,0) and 4 - i from (4,0): min(3 + i, 0.5 + 4 - i).
  // (0,0) keeps its own 3 (through (4,0): 4.5). 1e-5: float sums of a few unit lengths.
  for (int i = 0; i <= 4; ++i)
    EXPECT_NEAR(d[2 * i], std::min(3.0f + float(i), 4.5f - float(i)), 1e-5f) << "bottom " << i;
  // A vertex's own start is a path of length 0; one left at +infinity is reached by paths.
  EXPECT_NEAR(d[2 * 4 + 1], 1.5f, 1e-5f);  // (4,1): up from (4,0)
  for (std::size_t v = s.positions.size() - 3; v < s.positions.size(); ++v)
    EXPECT_TRUE(std::isinf(d[v])) << v;
  EXPECT_THROW(distance_along_edges(vertex_adjacency(s.positions, s.indices),
                                    std::vector<float>(3, 0.0f)),
               std::invalid_argument);
}

TEST(SurfaceDistance, RefusesMismatchedInput) {
  const Strip s = strip(2);
  EXPECT_THROW(
      distance_along_edges(vertex_adjacency(s.positions, s.indices), std::vector<bool>(3, true)),
      std::invalid_argument);
  std::vector<std::uint32_t> partial(s.indices.begin(), s.indices.begin() + 4);
  EXPECT_THROW(vertex_adjacency(s.positions, partial), std::invalid_argument);
  std::vector<std::uint32_t> outside = s.indices;
  outside[0] = 1000;
  EXPECT_THROW(vertex_adjacency(s.positions, outside), std::invalid_argument);
}

TEST(VertexAdjacency, ListsEachNeighbourOnceAscendingWithItsEdgeLength) {
  const Strip s = strip(2);
  const VertexAdjacency adjacency = vertex_adjacency(s.positions, s.indices);
  ASSERT_EQ(adjacency.vertex_count(), s.positions.size());
  // (1,0) = vertex 2 touches (0,0), (1,1), (2,0) and, by the diagonal from (i,0) to (i+1,1),
  // (2,1); not (0,1). Compared exactly: sqrt of an exact 1 or 2, as glm::length computes it.
  const std::span<const std::uint32_t> ring = adjacency.neighbours(2);
  EXPECT_EQ(std::vector<std::uint32_t>(ring.begin(), ring.end()),
            (std::vector<std::uint32_t>{0, 3, 4, 5}));
  const std::span<const float> lengths = adjacency.lengths(2);
  EXPECT_EQ(std::vector<float>(lengths.begin(), lengths.end()),
            (std::vector<float>{1.0f, 1.0f, 1.0f, std::sqrt(2.0f)}));
}

}  // namespace
}  // namespace sweepd::deform
