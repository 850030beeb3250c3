// RegionMeter's flipped triangles (metrics/region_quality.h), the count that decides the corpus
// gate's worse (frame, region) pairs where the stretch does not: a rigid motion of the whole
// body flips nothing, a triangle folded over its opposite edge counts in its own region, and a
// triangle of zero rest area never counts (it has no rest normal to point away from), and a
// triangle counts in the region of each of its corners whichever corner comes first; and its
// edges: one between two regions counts in both, whichever way the triangles wind. On the 6k
// mannequin, moved by hand so that every expected figure is known exactly.
#include "metrics/region_quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

// The rest mesh with a triangle's first corner reflected through the midpoint of the opposite
// edge (v0' = v1 + v2 - v0), which turns the triangle's normal exactly around at the same area;
// every copy of the corner (the mesh has seam copies) moves with it.
std::vector<glm::vec3> folded_over_opposite_edge(const deform::Model& model,
                                                 const std::uint32_t* corner) {
  std::vector<glm::vec3> positions = model.positions;
  const glm::vec3 from = positions[corner[0]];
  const glm::vec3 to = positions[corner[1]] + positions[corner[2]] - from;
  for (glm::vec3& p : positions)
    if (p == from) p = to;
  return positions;
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
  // A swept triangle of the torso whose first corner's triangles lie wholly in the torso, folded
  // over its opposite edge.
  const std::size_t triangle_count = model.indices.size() / 3;
  auto region_of = [&](std::uint32_t v) { return labels.regions[labels.region_of_vertex[v]]; };
  auto corner_counts_in_torso = [&](glm::vec3 corner) {
    for (std::size_t u = 0; u < triangle_count; ++u) {
      const std::uint32_t* c = &model.indices[3 * u];
      if (model.positions[c[0]] != corner && model.positions[c[1]] != corner &&
          model.positions[c[2]] != corner)
        continue;
      for (int k = 0; k < 3; ++k)
        if (region_of(c[k]) != deform::BodyPart::kTorso) return false;
    }
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
  const std::vector<glm::vec3> positions = folded_over_opposite_edge(model, corner);
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

// The same body with every triangle's corners rotated (a, b, c) -> (b, c, a), as a re-export
// may write them: the same triangles, the same windings.
deform::BoundModel corners_rotated(const deform::BoundModel& bound) {
  deform::BoundModel rotated = bound;
  std::vector<std::uint32_t>& indices = rotated.model.indices;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    std::rotate(indices.begin() + t, indices.begin() + t + 1, indices.begin() + t + 3);
  return rotated;
}

// Per region, RegionMeter's flipped triangles equal SweptStretchMeter's (the self-check's) over
// the swept ones.
void expect_lean_meter_agrees(const deform::BoundModel& bound,
                              const std::vector<glm::vec3>& positions,
                              const std::vector<glm::mat4>& world,
                              const std::vector<RegionFigures>& figures) {
  std::vector<glm::vec3> lean_positions;
  std::vector<RegionFigures> lean;
  const SweptStretchMeter lean_meter(bound);
  lean_meter.gather(positions, lean_positions);
  lean_meter.measure(lean_positions, world, lean);
  ASSERT_EQ(lean.size(), figures.size());
  for (std::size_t r = 0; r < figures.size(); ++r)
    EXPECT_EQ(lean[r].swept_flipped, figures[r].swept_flipped) << r;
}

// RegionMeter's figures of the body as it is and with its corners rotated (corners_rotated),
// each checked against the self-check's meter.
std::array<std::vector<RegionFigures>, 2> measured_as_is_and_rotated(
    const deform::BoundModel& bound, const std::vector<glm::vec3>& positions,
    const std::vector<glm::mat4>& world) {
  const deform::BoundModel rotated = corners_rotated(bound);
  std::array<std::vector<RegionFigures>, 2> figures = {
      RegionMeter(bound).measure(positions, world), RegionMeter(rotated).measure(positions, world)};
  expect_lean_meter_agrees(bound, positions, world, figures[0]);
  expect_lean_meter_agrees(rotated, positions, world, figures[1]);
  return figures;
}

// A triangle whose corners lie in two regions counts in both, whichever corner comes first: with
// "the region of its first corner", a re-export that rotates corners moved triangles at every
// region border from one region to the other, as edges moved with their winding before.
TEST(RegionMeterFlips, ATriangleBetweenRegionsCountsInEachWhicheverCornerComesFirst) {
  const deform::BoundModel& bound = mannequin_binding();
  const deform::Model& model = bound.model;
  const RegionLabels labels = label_regions(bound);
  const std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  // A swept triangle whose first two corners lie in two regions, folded over its opposite edge
  // as above.
  std::size_t t = 0;
  for (; 3 * t + 2 < model.indices.size(); ++t) {
    const std::uint32_t* c = &model.indices[3 * t];
    if (labels.region_of_vertex[c[0]] != labels.region_of_vertex[c[1]] &&
        bound.vertices[c[0]].skin_weight < 1.0f)
      break;
  }
  ASSERT_LT(3 * t + 2, model.indices.size()) << "the mannequin has no triangle between regions";
  const std::uint32_t* corner = &model.indices[3 * t];
  const std::vector<glm::vec3> positions = folded_over_opposite_edge(model, corner);
  const auto [figures, rotated_figures] = measured_as_is_and_rotated(bound, positions, world);
  // The folded triangle counts in both its corners' regions.
  for (const int region :
       {labels.region_of_vertex[corner[0]], labels.region_of_vertex[corner[1]]}) {
    EXPECT_GE(figures[region].flipped, 1) << deform::to_string(labels.regions[region]);
    EXPECT_GE(figures[region].swept_flipped, 1);
  }
  // Rotated, the same triangles flip in the same regions.
  ASSERT_EQ(figures.size(), rotated_figures.size());
  for (std::size_t r = 0; r < figures.size(); ++r) {
    EXPECT_EQ(figures[r].flipped, rotated_figures[r].flipped)
        << deform::to_string(labels.regions[r]);
    EXPECT_EQ(figures[r].swept_flipped, rotated_figures[r].swept_flipped);
  }
}

// Flipped means no turn of a bone the triangle hangs on explains its normal: it is judged against
// each of its corners' strongest joints, so the order of its corners does not decide it either.
// The mesh as it rests while the left leg's and foot's joints are turned half a turn about the
// vertical: the triangles of the leg (every corner on a turned joint, facing sideways) point away
// from their rest normals so turned and flip; a triangle at the hip, with a corner on the
// pelvis, is explained by the pelvis (not turned) and does not.
TEST(RegionMeterFlips, ATriangleFlipsOnlyAgainstTheTurnOfEachOfItsCornersJoints) {
  const deform::BoundModel& bound = mannequin_binding();
  const deform::Model& model = bound.model;
  const RegionLabels labels = label_regions(bound);
  const std::vector<deform::BodyPart> part = deform::label_joints(bound.rig, model.skeleton);
  const glm::mat4 half_turn =
      glm::rotate(glm::mat4(1.0f), glm::radians(180.0f), glm::vec3(0, 1, 0));
  std::vector<glm::mat4> world = model.skeleton.world_rest_matrices();
  std::vector<bool> turned(world.size(), false);
  for (std::size_t j = 0; j < world.size(); ++j)
    if (part[j] == deform::BodyPart::kLeftLeg || part[j] == deform::BodyPart::kLeftFoot) {
      world[j] = half_turn * world[j];
      turned[j] = true;
    }
  const std::vector<glm::vec3>& positions = model.positions;
  const auto [figures, rotated_figures] = measured_as_is_and_rotated(bound, positions, world);
  // Expected: the triangles with every corner on a turned joint whose rest normal the half turn
  // takes more than 90° away (not pointing up or down), in each of their corners' regions.
  std::vector<int> expected(labels.regions.size(), 0);
  int mixed = 0;  // triangles with corners on turned and on other joints, turned by the half turn
  for (std::size_t t = 0; 3 * t + 2 < model.indices.size(); ++t) {
    const std::uint32_t* c = &model.indices[3 * t];
    const int on_turned = turned[labels.strongest_joint[c[0]]] +
                          turned[labels.strongest_joint[c[1]]] +
                          turned[labels.strongest_joint[c[2]]];
    const glm::vec3 n = triangle_normal(positions, model.indices, t);
    const bool away = glm::dot(n, glm::mat3(half_turn) * n) < 0.0f;
    mixed += on_turned > 0 && on_turned < 3 && away;
    if (on_turned < 3 || !away) continue;
    for (const int region :
         triangle_regions(labels.region_of_vertex[c[0]], labels.region_of_vertex[c[1]],
                          labels.region_of_vertex[c[2]]))
      if (region >= 0) ++expected[region];
  }
  ASSERT_GT(mixed, 0) << "no triangle at the hip that the first-corner rule would judge by order";
  ASSERT_EQ(figures.size(), expected.size());
  int total = 0;
  for (std::size_t r = 0; r < figures.size(); ++r) {
    EXPECT_EQ(figures[r].flipped, expected[r]) << deform::to_string(labels.regions[r]);
    EXPECT_EQ(rotated_figures[r].flipped, expected[r]) << deform::to_string(labels.regions[r]);
    total += expected[r];
  }
  EXPECT_GT(total, 100);  // most of the leg's triangles face sideways
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
