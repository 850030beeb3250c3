// Where the closed arm region's volume goes when the elbow of the shared male bends to 150°
// with the paper's volume correction (the integral held at rest): the region's change split
// into what blending with the torso and the skinned hand does, what the offsets c along N do,
// what the swept ellipses themselves do (the signed swept volume, inner fold included), and
// what the vertices' displacements from their ellipses do. The elbow key is centred on the
// joint, but its ellipse is offset onto the elbow's section (KeyEllipse::offset), so the
// displacements stay small and the region follows the integral. (With the ellipse on the
// joint, 2.2 cm outside the section's centroid, the displacements cost the region 11.3 points.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "deform/binding/cross_section.h"
#include "deform/binding/polygon_ellipse.h"
#include "deform/binding/sweep_coordinates.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/sweep/swept_volume.h"
#include "deform/volume/part_volume_regions.h"
#include "deform/volume/volume_preservation.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// The region's vertices as the posed arm sweep alone would place them.
enum class Skin {
  kActual,             // the DeformJob's output (blends, skinned share)
  kSweepOnly,          // every arm-bound vertex from its arm sweep coordinate alone
  kSweepOnlyWithoutC,  // the same with the offset c along N dropped
  kOnEllipse,          // the same, c and the displacement (da, db) dropped: on the ellipse
};
constexpr Skin kSkins[] = {Skin::kActual, Skin::kSweepOnly, Skin::kSweepOnlyWithoutC,
                           Skin::kOnEllipse};

std::vector<glm::vec3> skin(const BoundModel& male, int arm, const Sweep& sweep,
                            std::span<const glm::vec3> actual, Skin mode) {
  std::vector<glm::vec3> out(actual.begin(), actual.end());
  if (mode == Skin::kActual) return out;
  for (std::size_t v = 0; v < out.size(); ++v)
    for (int k = 0; k < kSweepsPerVertex; ++k) {
      if (male.vertices[v].sweep[k] != arm) continue;
      SweepCoordinate c = male.vertices[v].coordinate[k];
      if (mode != Skin::kSweepOnly) c.c = 0.0f;
      if (mode == Skin::kOnEllipse) c.da = c.db = 0.0f;
      out[v] = evaluate_point(sweep, c);
    }
  return out;
}

// % changes against rest at one elbow angle: the integral and the region for each Skin.
struct Budget {
  double integral;
  double region[4];
};

// With the paper's volume correction (no folding, so I_C = 0).
Budget budget(const BoundModel& male, float degrees) {
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  PartVolumeRegions regions(male);
  test::Posing deformer(male);
  deformer.features.volume = true;
  auto measure = [&](float angle, double* integral, double* region) {
    const auto positions =
        test::deformed(deformer, test::left_elbow_bent(male.model, angle), DeformMethod::kSweep);
    const Sweep& sweep = deformer.sweep_poser().sweep(arm);
    *integral = sweep_volume(sweep);
    for (int i = 0; i < 4; ++i)
      region[i] = regions.volume(arm, skin(male, arm, sweep, positions, kSkins[i]));
  };
  double rest_integral, rest_region[4], integral, region[4];
  measure(0.0f, &rest_integral, rest_region);
  measure(degrees, &integral, region);
  Budget result{100 * (integral / rest_integral - 1), {}};
  for (int i = 0; i < 4; ++i) result.region[i] = 100 * (region[i] / rest_region[i] - 1);
  std::printf(
      "elbow %.0f°, %% vs rest: integral %+.2f | region: actual %+.2f, sweep only %+.2f, "
      "without c %+.2f, on the ellipses %+.2f\n",
      degrees, result.integral, result.region[0], result.region[1], result.region[2],
      result.region[3]);
  return result;
}

// The rest mesh's cross-section at the elbow key: the elbow key and its section's centroid.
struct ElbowSection {
  KeyEllipse key;
  glm::vec3 centroid;
};
ElbowSection elbow_section(const BoundModel& male) {
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  const BoundSweep& sweep = male.sweeps[arm];
  int elbow = 0;
  while (sweep.anchors[elbow].joint != male.rig.left_arm.lower ||
         !sweep.anchors[elbow].is_joint_key())
    ++elbow;
  const KeyEllipse& key = sweep.rest_keys[elbow];
  const glm::vec3 normal = glm::mat3_cast(key.orientation)[2];
  std::size_t count = 0;  // welded, so the cut loop closes at UV seams
  const std::vector<std::uint32_t> id = weld_coincident_positions(male.model.positions, &count);
  std::vector<glm::vec3> positions(count);
  for (std::size_t v = 0; v < id.size(); ++v) positions[id[v]] = male.model.positions[v];
  std::vector<std::uint32_t> indices(male.model.indices.size());
  for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = id[male.model.indices[i]];
  const PlaneFrame frame = make_plane_frame(key.centre, normal);
  const CrossSection cut = cross_section(positions, indices, frame, key.centre);
  const EllipseFit fit = fit_polygon_ellipse(cut.points_2d);
  return {key, key.centre + fit.centre.x * frame.x_axis + fit.centre.y * frame.y_axis};
}

TEST(ArmVolumeBudget, AtABentElbowTheRegionFollowsTheIntegral) {
  REQUIRE_SHARED_MALE();
  const Budget b = budget(male, 150.0f);
  // Measured: integral -0.00, actual +1.64, sweep only +1.56, without c +1.60, on the
  // ellipses -0.46 (%).
  EXPECT_LT(std::abs(b.integral), 0.5);  // the correction holds I (tolerance 0.1 %)
  // Blending with the torso and the skinned hand inside the region: a small share (-0.23
  // measured; the region's vertices follow the arm sweep alone or blend where the caps are).
  EXPECT_LT(std::abs(b.region[0] - b.region[1]), 0.5);
  // The offsets c along N: 0.00 measured.
  EXPECT_LT(std::abs(b.region[1] - b.region[2]), 0.2);
  // Skin on the ellipses is the signed swept volume with the region's caps: it follows I
  // (-0.46 measured), inner fold and all — the region and the sweep cover the same extent.
  EXPECT_LT(std::abs(b.region[3] - b.integral), 1.0);
  // The displacements from the ellipses: +2.06 points measured (-11.30 with the elbow's
  // ellipse on the joint; +1.32 before the mitred elbow key spread the outer skin).
  EXPECT_LT(std::abs(b.region[2] - b.region[3]), 2.5);
  EXPECT_LT(std::abs(b.region[0]), 2.0);  // the bound on the closed region
}

TEST(ArmVolumeBudget, TheElbowKeyIsOnItsJointAndItsEllipseOnTheSection) {
  REQUIRE_SHARED_MALE();
  const ElbowSection elbow = elbow_section(male);
  const glm::mat3 frame = glm::mat3_cast(elbow.key.orientation);
  const glm::vec3 ellipse_centre = elbow.key.centre + frame * glm::vec3(elbow.key.offset, 0.0f);
  const glm::vec3 inner =
      glm::normalize(glm::cross(test::left_elbow_flexion_axis(male.model), frame[2]));
  const float from_key = glm::dot(elbow.centroid - elbow.key.centre, inner);
  const float from_ellipse = glm::length(elbow.centroid - ellipse_centre);
  std::printf(
      "elbow section centroid: %.2f cm on the inner side of the key's centre (the joint), "
      "%.2f cm from its ellipse's centre\n",
      100 * from_key, 100 * from_ellipse);
  // The key is the joint (C(t) passes through it, so the bend turns the far spans rigidly),
  // to float rounding of the joint's world position.
  const glm::vec3 joint(male.model.skeleton.world_rest_matrices()[male.rig.left_arm.lower][3]);
  EXPECT_LT(glm::length(elbow.key.centre - joint), 1e-5f);
  // Measured 2.2 cm: turning about the joint, the bend carries the section's first moment to
  // the inner side; the offset ellipse carries it the same way, so the integral sees it.
  EXPECT_GT(from_key, 0.015f);
  EXPECT_LT(from_ellipse, 0.003f);  // 0.0 measured: the fit's own centroid
}

}  // namespace
}  // namespace sweepd::deform
