// Self-intersection detection (grid broad phase + exact test) on configurations with known
// answers: interpenetrating and separated boxes, mesh neighbours, crossing and near-miss
// sheets, and the all-pairs reference on random soups.
#include "deform/features/self_intersection.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "tests/deform/collision_shapes.h"

namespace sweepd::deform {
namespace {

using testing::SoupMesh;

std::vector<TrianglePair> detect(const SoupMesh& mesh) {
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(mesh.positions, mesh.indices, mesh.all_triangles(), pairs);
  return pairs;
}

TEST(SelfIntersection, InterpenetratingBoxesMeetOnExactlyTheKnownFaces) {
  // Unit box A and box B = A + 0.5: A's +x/+y/+z faces cross B's -x/-y/-z faces, except the
  // parallel ones (A's +x with B's -x, ...). No other face pair shares a point.
  SoupMesh mesh;
  testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  testing::add_box(mesh, glm::vec3(0.5f), glm::vec3(1.5f));
  const std::vector<TrianglePair> pairs = detect(mesh);
  std::set<std::pair<int, int>> faces;  // (face of A, face of B), faces numbered -x,+x,-y,...
  for (const TrianglePair& p : pairs) {
    ASSERT_LT(p.first, 12u) << "a pair inside one box";
    ASSERT_GE(p.second, 12u) << "a pair inside one box";
    faces.insert({static_cast<int>(p.first / 2), static_cast<int>((p.second - 12) / 2)});
  }
  const std::set<std::pair<int, int>> expected = {{1, 2}, {1, 4}, {3, 0}, {3, 4}, {5, 0}, {5, 2}};
  EXPECT_EQ(faces, expected);
  EXPECT_EQ(pairs, testing::all_pairs_reference(mesh, mesh.all_triangles()));
}

TEST(SelfIntersection, SeparatedBoxesAndNearMissesGiveNoPairs) {
  SoupMesh mesh;
  testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  testing::add_box(mesh, glm::vec3(1.0001f, 0.0f, 0.0f),
                   glm::vec3(2.0f, 1.0f, 1.0f));                       // 0.1 mm gap
  testing::add_grid(mesh, {0, 1.00001f, 0}, {1, 0, 0}, {0, 0, 1}, 4);  // 10 µm above box A
  EXPECT_TRUE(detect(mesh).empty());
}

TEST(SelfIntersection, MeshNeighboursSharingVerticesAreNotPairs) {
  // A flat grid: every triangle touches its neighbours along edges or at corners.
  SoupMesh grid;
  testing::add_grid(grid, glm::vec3(0.0f), {1, 0, 0}, {0, 1, 0}, 8);
  EXPECT_TRUE(detect(grid).empty());
  // A closed box alone: all its triangles meet only at shared vertices.
  SoupMesh box;
  testing::add_box(box, glm::vec3(-1.0f), glm::vec3(2.0f));
  EXPECT_TRUE(detect(box).empty());
}

TEST(SelfIntersection, CrossingSheetsPairOnlyAcrossTheSheets) {
  // Sheet A in z = 0, sheet B in the plane x = 0.37 (between grid lines), crossing A.
  SoupMesh mesh;
  testing::add_grid(mesh, glm::vec3(0.0f), {1, 0, 0}, {0, 1, 0}, 10);
  const std::uint32_t sheet_a = mesh.triangle_count();
  testing::add_grid(mesh, {0.37f, -0.5f, -0.5f}, {0, 2, 0}, {0, 0, 1}, 10);
  const std::vector<TrianglePair> pairs = detect(mesh);
  ASSERT_FALSE(pairs.empty());
  std::set<std::uint32_t> floor_columns;
  for (const TrianglePair& p : pairs) {
    ASSERT_LT(p.first, sheet_a);
    ASSERT_GE(p.second, sheet_a);
    floor_columns.insert(p.first / 2 % 10);  // the x column of the floor quad
  }
  // The line x = 0.37 runs through floor column 3 (x in [0.3, 0.4]) only.
  EXPECT_EQ(floor_columns, std::set<std::uint32_t>{3});
  EXPECT_EQ(pairs, testing::all_pairs_reference(mesh, mesh.all_triangles()));
}

TEST(SelfIntersection, GridBroadPhaseMatchesAllPairsOnRandomSoups) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const SoupMesh soup = testing::random_soup(600, 0.06f, seed);
    const std::vector<TrianglePair> pairs = detect(soup);
    EXPECT_GT(pairs.size(), 20u) << "seed " << seed << ": too few pairs to compare";
    EXPECT_EQ(pairs, testing::all_pairs_reference(soup, soup.all_triangles())) << "seed " << seed;
  }
}

TEST(SelfIntersection, OnlyTheListedTrianglesAreTested) {
  SoupMesh mesh;
  testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  testing::add_box(mesh, glm::vec3(0.5f), glm::vec3(1.5f));
  // Box A's +x face (triangles 2, 3) against box B's -y face (triangles 16, 17) only.
  const std::vector<std::uint32_t> subset = {17, 2, 16, 3};
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(mesh.positions, mesh.indices, subset, pairs);
  EXPECT_EQ(pairs, testing::all_pairs_reference(mesh, subset));
  EXPECT_FALSE(pairs.empty());
  for (const TrianglePair& p : pairs) {
    EXPECT_TRUE(p.first == 2 || p.first == 3);
    EXPECT_TRUE(p.second == 16 || p.second == 17);
  }
}

TEST(SelfIntersection, TrianglesWithNonFiniteCornersAreLeftOut) {
  // Two interpenetrating boxes with one corner of each made non-finite: the triangles using
  // those corners meet nothing, the others give exactly the pairs they give without them.
  SoupMesh mesh;
  testing::add_box(mesh, glm::vec3(0.0f), glm::vec3(1.0f));
  testing::add_box(mesh, glm::vec3(0.5f), glm::vec3(1.5f));
  const std::uint32_t nan_corner = 9, infinite_corner = 3;
  mesh.positions[nan_corner].x = NAN;
  mesh.positions[infinite_corner].z = INFINITY;
  std::vector<std::uint32_t> finite;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    bool uses = false;
    for (int k = 0; k < 3; ++k)
      uses = uses || mesh.indices[3 * t + k] == nan_corner ||
             mesh.indices[3 * t + k] == infinite_corner;
    if (!uses) finite.push_back(t);
  }
  ASSERT_LT(finite.size(), mesh.triangle_count()) << "the corners are used by some triangle";
  const std::vector<TrianglePair> pairs = detect(mesh);
  EXPECT_FALSE(pairs.empty()) << "the finite faces still cross";
  EXPECT_EQ(pairs, testing::all_pairs_reference(mesh, finite));

  // Every triangle with a non-finite corner: nothing to pair, and no grid over no extent.
  SoupMesh lone;
  testing::add_box(lone, glm::vec3(0.0f), glm::vec3(1.0f));
  for (std::size_t v = 1; v < lone.positions.size(); ++v) lone.positions[v] = glm::vec3(NAN);
  EXPECT_TRUE(detect(lone).empty());
}

}  // namespace
}  // namespace sweepd::deform
