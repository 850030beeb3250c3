// Skin folding on a configuration with a known answer: two closed boxes standing for the skin
// before and past a joint, pushed 5 cm into each other. Folding must separate them exactly at
// the bisecting plane, leave the far ends alone, and report the volume taken out. Relaxing
// smooths a spike through a plate and nothing else; separate folds get separate planes.
#include "deform/features/skin_folding.h"

#include <gtest/gtest.h>

#include "deform/mesh/enclosed_volume.h"
#include "tests/deform/collision_shapes.h"

namespace sweepd::deform {
namespace {

struct TwoBoxes {
  testing::SoupMesh mesh;
  CollisionRegion region;
  std::uint32_t first_past = 0;  // vertices from here on belong to the box past the joint
};

// Box "before" spans x in [-1, 0.05], box "past" x in [-0.05, 1]; both 1 m x 1 m across.
TwoBoxes interpenetrating_boxes() {
  TwoBoxes boxes;
  testing::add_subdivided_box(boxes.mesh, {-1.0f, -0.5f, -0.5f}, {0.05f, 0.5f, 0.5f}, 20);
  boxes.first_past = static_cast<std::uint32_t>(boxes.mesh.positions.size());
  testing::add_subdivided_box(boxes.mesh, {-0.05f, -0.5f, -0.5f}, {1.0f, 0.5f, 0.5f}, 20);
  for (std::uint32_t v = 0; v < boxes.mesh.positions.size(); ++v) {
    boxes.region.vertices.push_back(v);
    boxes.region.sides.push_back(v < boxes.first_past ? -1 : 1);
  }
  boxes.region.triangles = boxes.mesh.all_triangles();
  measure_rest_edges(boxes.region, boxes.mesh.positions, boxes.mesh.indices);
  return boxes;
}

TEST(SkinFolding, FitPlaneFindsTheSmallestVarianceDirection) {
  // Points on a tilted plane through (1, 2, 3): the fit returns its normal up to sign.
  const glm::vec3 normal = glm::normalize(glm::vec3(1, -2, 0.5f));
  const glm::vec3 u = glm::normalize(glm::cross(normal, glm::vec3(0, 0, 1)));
  const glm::vec3 v = glm::cross(normal, u);
  std::vector<glm::vec3> points;
  for (int i = -3; i <= 3; ++i) {
    for (int j = -2; j <= 2; ++j)
      points.push_back(glm::vec3(1, 2, 3) + u * float(i) + v * float(j));
  }
  glm::vec3 centroid;
  const glm::vec3 fitted = fit_plane(points, centroid);
  // float round-off of coordinates near 3 m.
  EXPECT_NEAR(std::abs(glm::dot(fitted, normal)), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(centroid, glm::vec3(1, 2, 3)), 0.0f, 1e-5f);
}

TEST(SkinFolding, InterpenetratingBoxesAreSeparatedAtTheBisectingPlane) {
  TwoBoxes boxes = interpenetrating_boxes();
  testing::SoupMesh& mesh = boxes.mesh;
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(mesh.positions, mesh.indices, boxes.region.triangles, pairs);
  ASSERT_FALSE(pairs.empty());
  const std::vector<glm::vec3> before = mesh.positions;
  const double volume_before = enclosed_volume(mesh.positions, mesh.indices, mesh.all_triangles());

  const float gap = 1e-3f;
  SkinFolder folder;
  const FoldingResult result = folder.fold(boxes.region, mesh.indices, pairs, gap, mesh.positions);
  EXPECT_EQ(result.groups, 1);
  // Each box's end face went 5 cm through the plane x = 0 (float grid coordinates).
  EXPECT_NEAR(result.max_depth, 0.05f, 1e-5f);
  // The end faces' 21 x 21 vertices of each box had gone through.
  EXPECT_EQ(result.moved, 2 * 21 * 21);

  detector.detect(mesh.positions, mesh.indices, boxes.region.triangles, pairs);
  EXPECT_TRUE(pairs.empty()) << pairs.size() << " pairs left";
  float before_max_x = -1.0f, past_min_x = 1.0f;
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3& p = mesh.positions[v];
    if (v < boxes.first_past)
      before_max_x = std::max(before_max_x, p.x);
    else
      past_min_x = std::min(past_min_x, p.x);
    // Only along the plane's normal, x up to the fit's round-off; the far ends
    // (|x| > band = 0.1 + 4 gap) stay put exactly.
    EXPECT_NEAR(p.y, before[v].y, 1e-6f);
    EXPECT_NEAR(p.z, before[v].z, 1e-6f);
    if (std::abs(before[v].x) > 0.11f) {
      EXPECT_EQ(p.x, before[v].x);
    }
  }
  // Each end face lands `gap` behind the plane (float round-off of the linear map).
  EXPECT_NEAR(before_max_x, -gap, 1e-6f);
  EXPECT_NEAR(past_min_x, gap, 1e-6f);
  // Each box lost (0.05 + gap) m of its 1 m² cross-section; the fold reports it (round-off of
  // float coordinates summed over 4800 triangles).
  const double volume_after = enclosed_volume(mesh.positions, mesh.indices, mesh.all_triangles());
  EXPECT_NEAR(volume_after - volume_before, -2.0 * (0.05 + gap), 1e-5);
  EXPECT_NEAR(result.volume_change, volume_after - volume_before, 1e-6);
}

TEST(SkinFolding, SeparateGroupsEachGetTheirOwnPlane) {
  // The boxes of interpenetrating_boxes (meeting across x = 0), and a second pair 5 m away
  // meeting across y = 5: one plane fitted to both groups would cut neither fold.
  TwoBoxes boxes = interpenetrating_boxes();
  testing::SoupMesh& mesh = boxes.mesh;
  const auto first_second_pair = static_cast<std::uint32_t>(mesh.positions.size());
  testing::add_subdivided_box(mesh, {-0.5f, 4.0f, 4.5f}, {0.5f, 5.05f, 5.5f}, 10);
  const auto second_past = static_cast<std::uint32_t>(mesh.positions.size());
  testing::add_subdivided_box(mesh, {-0.5f, 4.95f, 4.5f}, {0.5f, 6.0f, 5.5f}, 10);
  for (std::uint32_t v = first_second_pair; v < mesh.positions.size(); ++v) {
    boxes.region.vertices.push_back(v);
    boxes.region.sides.push_back(v < second_past ? -1 : 1);
  }
  boxes.region.triangles = mesh.all_triangles();
  measure_rest_edges(boxes.region, mesh.positions, mesh.indices);
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(mesh.positions, mesh.indices, boxes.region.triangles, pairs);
  ASSERT_FALSE(pairs.empty());
  SkinFolder folder;
  const FoldingResult result =
      folder.fold(boxes.region, mesh.indices, pairs, 1e-3f, mesh.positions);
  EXPECT_EQ(result.groups, 2);
  // Both went 5 cm through their own plane (float grid coordinates).
  EXPECT_NEAR(result.max_depth, 0.05f, 1e-5f);
  detector.detect(mesh.positions, mesh.indices, boxes.region.triangles, pairs);
  EXPECT_TRUE(pairs.empty()) << pairs.size() << " pairs left";
}

TEST(SkinFolding, NoPairsMovesNothing) {
  TwoBoxes boxes = interpenetrating_boxes();
  const std::vector<glm::vec3> before = boxes.mesh.positions;
  SkinFolder folder;
  const FoldingResult result =
      folder.fold(boxes.region, boxes.mesh.indices, {}, 1e-3f, boxes.mesh.positions);
  EXPECT_EQ(result.moved, 0);
  EXPECT_EQ(result.groups, 0);
  EXPECT_EQ(boxes.mesh.positions, before);
}

TEST(SkinFolding, RelaxSmoothsOnlyTheIntersectingTrianglesCorners) {
  // A 1 m grid (10 x 10 cells) in z = 0 whose middle vertex is pulled 0.3 m up, and a small
  // plate it pokes through at z = 0.2.
  testing::SoupMesh mesh;
  testing::add_grid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10);
  const std::uint32_t grid_vertices = static_cast<std::uint32_t>(mesh.positions.size());
  const std::uint32_t spike = 5 * 11 + 5;
  mesh.positions[spike].z = 0.3f;
  testing::add_grid(mesh, {0.4f, 0.4f, 0.2f}, {0.2f, 0, 0}, {0, 0.2f, 0}, 1);
  CollisionRegion region;
  for (std::uint32_t v = 0; v < grid_vertices; ++v)
    region.vertices.push_back(v), region.sides.push_back(-1);
  region.triangles = mesh.all_triangles();
  measure_rest_edges(region, mesh.positions, mesh.indices);
  SelfIntersectionDetector detector;
  std::vector<TrianglePair> pairs;
  detector.detect(mesh.positions, mesh.indices, region.triangles, pairs);
  ASSERT_FALSE(pairs.empty());
  std::vector<bool> corner(mesh.positions.size());
  for (const TrianglePair& p : pairs) {
    for (std::uint32_t t : {p.first, p.second}) {
      for (int k = 0; k < 3; ++k) corner[mesh.indices[3 * t + k]] = true;
    }
  }
  const std::vector<glm::vec3> before = mesh.positions;
  SkinFolder folder;
  folder.relax(region, mesh.indices, pairs, mesh.positions);
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    // The plate is outside the region and grid vertices away from the spike are no corners.
    if (v >= grid_vertices || !corner[v]) {
      EXPECT_EQ(mesh.positions[v], before[v]) << v;
    }
  }
  // Smoothing: the spike sinks below the plate (it ends well under half its height).
  EXPECT_LT(mesh.positions[spike].z, 0.15f);
  detector.detect(mesh.positions, mesh.indices, region.triangles, pairs);
  EXPECT_TRUE(pairs.empty()) << pairs.size() << " pairs left";
}

}  // namespace
}  // namespace sweepd::deform
