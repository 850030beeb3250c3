// RegionMeter's flipped triangles (metrics/region_quality.h), the count that decides the corpus
// gate's worse (frame, region) pairs where the stretch does not: a rigid motion of the whole
// body flips nothing, a triangle folded over its opposite edge counts in its own region, and a
// triangle of zero rest area never counts (it has no rest normal to point away from). On the
// 6k mannequin, moved by hand so that every expected figure is known exactly.
#include "metrics/region_quality.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "deform/binding/bind.h"
#include "mannequin/mannequin.h"

namespace sweepd::metrics {
namespace {

const deform::BoundModel& mannequin_binding() {
  static const deform::BoundModel bound = [] {
    const deform::Model model = mannequin::make_mannequin({.target_vertices = 6000});
    return deform::bind(model, deform::detect_rig_map(model.skeleton));
  }();
  return bound;
}

int total_flipped(const std::vector<RegionFigures>& figures) {
  int flipped = 0;
  for (const RegionFigures& f : figures) flipped += f.flipped;
  return flipped;
}

TEST(RegionMeterFlips, ARigidMotionOfTheWholeBodyFlipsNothingAndStretchesNothing) {
  const deform::BoundModel& bound = mannequin_binding();
  const RegionMeter meter(bound);
  // Turned 120° about a tilted axis and moved: every joint and vertex by the same transform,
  // so each triangle's normal is its rest normal carried by its joint.
  const glm::mat4 motion =
      glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, 1.5f)),
                  glm::radians(120.0f), glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f)));
  std::vector<glm::mat4> world = bound.model.skeleton.world_rest_matrices();
  for (glm::mat4& w : world) w = motion * w;
  std::vector<glm::vec3> positions;
  for (const glm::vec3& p : bound.model.positions) positions.push_back(glm::vec3(motion * glm::vec4(p, 1.0f)));
  const std::vector<RegionFigures> figures = meter.measure(positions, world);
  EXPECT_EQ(total_flipped(figures), 0);
  for (const RegionFigures& f : figures) {
    EXPECT_EQ(f.swept_flipped, 0);
    // Float rounding of a rigid transform: 1e-4 of an edge's length at most.
    EXPECT_NEAR(f.stretch, 1.0, 1e-4);
    EXPECT_NEAR(f.squash, 1.0, 1e-4);
  }
}

TEST(RegionMeterFlips, ATriangleFoldedOverItsOppositeEdgeCountsInItsOwnRegion) {
  const deform::BoundModel& bound = mannequin_binding();
  const deform::Model& model = bound.model;
  const RegionMeter meter(bound);
  const RegionLabels labels = label_regions(bound);
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  // A swept triangle of the torso whose first corner's triangles all count in the torso: that
  // corner reflected through the midpoint of the opposite edge (v0' = v1 + v2 - v0) turns the
  // triangle's normal exactly around at the same area. Every copy of the corner (the mesh has
  // seam copies) moves with it.
  const std::size_t triangle_count = model.indices.size() / 3;
  auto region_of = [&](std::uint32_t v) { return labels.regions[labels.region_of_vertex[v]]; };
  auto corner_counts_in_torso = [&](glm::vec3 corner) {
    for (std::size_t u = 0; u < triangle_count; ++u)
      for (int k = 0; k < 3; ++k)
        if (model.positions[model.indices[3 * u + k]] == corner &&
            region_of(model.indices[3 * u]) != deform::BodyPart::kTorso)
          return false;
    return true;
  };
  std::size_t t = 0;
  for (; t < triangle_count; ++t) {
    const std::uint32_t v0 = model.indices[3 * t];
    if (region_of(v0) == deform::BodyPart::kTorso && bound.vertices[v0].skin_weight < 1.0f &&
        corner_counts_in_torso(model.positions[v0]))
      break;
  }
  ASSERT_LT(t, triangle_count) << "the mannequin has no swept torso triangle";
  const std::uint32_t* corner = &model.indices[3 * t];
  std::vector<glm::vec3> positions = model.positions;
  const glm::vec3 from = positions[corner[0]];
  const glm::vec3 to = positions[corner[1]] + positions[corner[2]] - from;
  for (glm::vec3& p : positions)
    if (p == from) p = to;
  const std::vector<RegionFigures> figures = meter.measure(positions, world);
  const int region = labels.region_of_vertex[corner[0]];
  // The folded triangle, perhaps some of the moved corner's other triangles, all in the torso.
  EXPECT_GE(figures[region].flipped, 1);
  EXPECT_GE(figures[region].swept_flipped, 1);
  EXPECT_EQ(total_flipped(figures), figures[region].flipped);
}

TEST(RegionMeterFlips, ATriangleOfZeroRestAreaNeverCounts) {
  const deform::BoundModel& source = mannequin_binding();
  // The same body with one degenerate triangle added (corners 0, 0 and 1: zero area at rest and
  // in every pose), bound anew.
  deform::Model model = source.model;
  model.indices.insert(model.indices.end(), {0u, 0u, 1u});
  const deform::BoundModel bound = deform::bind(model, deform::detect_rig_map(model.skeleton));
  const RegionMeter meter(bound);
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  // Its corners moved apart and back through each other: its normal stays 0, so it never
  // points away from its rest normal (0 too).
  std::vector<glm::vec3> positions = model.positions;
  const RegionFigures rest_total = [&] {
    RegionFigures sum;
    for (const RegionFigures& f : meter.measure(positions, world)) sum.flipped += f.flipped;
    return sum;
  }();
  EXPECT_EQ(rest_total.flipped, 0);
  std::swap(positions[0], positions[1]);
  int degenerate_alone = 0;
  for (const RegionFigures& f : meter.measure(positions, world)) degenerate_alone += f.flipped;
  // Swapping two corners flips the real triangles around them; measured without the
  // degenerate one, the count is the same.
  const RegionMeter plain(source);
  EXPECT_EQ(degenerate_alone, total_flipped(plain.measure(positions, world)));
}

}  // namespace
}  // namespace sweepd::metrics
