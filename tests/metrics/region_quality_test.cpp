// RegionMeter's flipped triangles (metrics/region_quality.h), the count that decides the corpus
// gate's worse (frame, region) pairs where the stretch does not: a rigid motion of the whole
// body flips nothing, a triangle folded over its opposite edge counts in its own region, and a
// triangle of zero rest area never counts (it has no rest normal to point away from); and its
// edges: one between two regions counts in both, whichever way the triangles wind. On the 6k
// mannequin, moved by hand so that every expected figure is known exactly.
#include "metrics/region_quality.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <utility>
#include <vector>

#include "deform/binding/bind.h"
#include "mannequin/mannequin.h"
#include "metrics/swept_stretch_meter.h"

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

// An edge whose vertices lie in two regions counts in both, whichever way the triangles wind: a
// mirrored copy of a body reverses its windings, and with "the region of its first vertex" an
// edge at the RiggedFigure's ankle counted in the leg (LBS 2.12x on the range of motion) and in
// the mirrored copy's foot (its leg's worst 1.76x).
TEST(RegionMeterEdges, AnEdgeBetweenTwoRegionsCountsInBothWhicheverWayTheTrianglesWind) {
  const deform::BoundModel& bound = mannequin_binding();
  const deform::Model& model = bound.model;
  const RegionLabels labels = label_regions(bound);
  // A triangle edge between two regions, its second vertex moved so that it is 1.5x as long.
  std::uint32_t a = 0, b = 0;
  for (std::size_t c = 0; c < model.indices.size() && a == b; ++c) {
    const std::uint32_t p = model.indices[c], q = model.indices[c % 3 == 2 ? c - 2 : c + 1];
    if (labels.region_of_vertex[p] != labels.region_of_vertex[q]) {
      a = p;
      b = q;
    }
  }
  ASSERT_NE(a, b) << "the mannequin has no edge between two regions";
  std::vector<glm::vec3> positions = model.positions;
  const glm::vec3 from = positions[b];
  for (glm::vec3& p : positions)  // every seam copy of the vertex with it
    if (p == from) p = positions[a] + 1.5f * (from - positions[a]);
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  deform::BoundModel rewound = bound;
  for (std::size_t t = 0; t + 2 < rewound.model.indices.size(); t += 3)
    std::swap(rewound.model.indices[t + 1], rewound.model.indices[t + 2]);
  const std::vector<RegionFigures> figures = RegionMeter(bound).measure(positions, world);
  const std::vector<RegionFigures> rewound_figures = RegionMeter(rewound).measure(positions, world);
  for (const int region : {labels.region_of_vertex[a], labels.region_of_vertex[b]}) {
    // The moved edge's own ratio, within float rounding of its lengths (1e-5).
    EXPECT_GE(figures[region].stretch, 1.5 - 1e-5) << deform::to_string(labels.regions[region]);
    EXPECT_GE(rewound_figures[region].stretch, 1.5 - 1e-5);
  }
  // The same edges in the same regions, only visited in another order: equal figures.
  ASSERT_EQ(figures.size(), rewound_figures.size());
  for (std::size_t r = 0; r < figures.size(); ++r) {
    EXPECT_EQ(figures[r].stretch, rewound_figures[r].stretch) << deform::to_string(labels.regions[r]);
    EXPECT_EQ(figures[r].squash, rewound_figures[r].squash);
    EXPECT_EQ(figures[r].swept_stretch, rewound_figures[r].swept_stretch);
  }
  // The binding's self-check meter counts the edge in both regions too.
  std::vector<glm::vec3> lean_positions;
  std::vector<RegionFigures> lean;
  const SweptStretchMeter lean_meter(rewound);
  lean_meter.gather(positions, lean_positions);
  lean_meter.measure(lean_positions, world, lean);
  for (std::size_t r = 0; r < figures.size(); ++r) {
    if (!figures[r].swept) continue;
    // From squared lengths: within a few float roundings (1e-6).
    EXPECT_NEAR(lean[r].swept_stretch, figures[r].swept_stretch, 1e-6);
  }
}

}  // namespace
}  // namespace sweepd::metrics
