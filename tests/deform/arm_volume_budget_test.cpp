// Where the closed arm region's volume goes when the elbow of the shared male bends to 150°
// with the paper's volume correction (the integral held at rest): the region's change split
// into what blending with the torso and the skinned hand does, what the offsets c along N do,
// what the swept ellipses themselves do (the signed swept volume, inner fold included), and
// what the vertices' displacements from their ellipses do — the last is the gap, because the
// elbow key is centred on the joint while the elbow's section lies on the inner side of it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "deform/cross_section.h"
#include "deform/ellipse_fit.h"
#include "deform/mesh_topology.h"
#include "deform/part_regions.h"
#include "deform/sweep_coordinates.h"
#include "deform/sweep_volume.h"
#include "deform/volume_preservation.h"
#include "shared_male.h"

namespace sweepd::deform {
namespace {

// The region's vertices as the posed arm sweep alone would place them.
enum class Skin {
  kActual,             // the Deformer's output (blends, skinned share)
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

DeformOptions paper_correction(float bend_plane_degrees = 10.0f) {
  DeformOptions options;
  options.preserve_volume = true;
  options.volume.fold_feedback_iterations = 0;
  options.volume.bend_plane_degrees = bend_plane_degrees;
  return options;
}

Budget budget(const BoundModel& male, float degrees, const DeformOptions& options) {
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  PartRegions regions(male);
  Deformer deformer(male);
  deformer.set_options(options);
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

// The offset of the rest mesh's section centroid from the elbow key's centre, along the
// direction the forearm bends towards (the inner side), in metres.
float elbow_section_offset(const BoundModel& male) {
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
  const EllipseFit fit = fit_ellipse(cut.points_2d);
  const glm::vec3 offset = fit.centre.x * frame.x_axis + fit.centre.y * frame.y_axis;
  const glm::vec3 inner = glm::cross(test::left_elbow_flexion_axis(male.model), normal);
  return glm::dot(offset, glm::normalize(inner));
}

const BoundModel& section_centred_male(const BoundModel& male) {
  static const BoundModel bound = [&] {
    BindOptions options;
    options.joint_key_centre = JointKeyCentre::kAtSectionCentroid;
    return bind(male.model, male.rig, options);
  }();
  return bound;
}

TEST(ArmVolumeBudget, TheGapAtABentElbowIsTheDisplacementOfAnOffCentreSection) {
  REQUIRE_SHARED_MALE();
  const Budget b = budget(male, 150.0f, paper_correction());
  // Measured: integral +0.00, actual -11.41, sweep only -11.41, without c -11.49, on the
  // ellipses -0.19 (%).
  EXPECT_LT(std::abs(b.integral), 0.5);  // the correction holds I (tolerance 0.1 %)
  // Blending with the torso and the skinned hand inside the region: no share (0.00 measured;
  // the region's vertices follow the arm sweep alone or blend where the caps are).
  EXPECT_LT(std::abs(b.region[0] - b.region[1]), 0.05);
  // The offsets c along N: 0.08 measured.
  EXPECT_LT(std::abs(b.region[1] - b.region[2]), 0.2);
  // Skin on the ellipses is the signed swept volume with the region's caps: it follows I
  // (0.19 measured), inner fold and all — the region and the sweep cover the same extent.
  EXPECT_LT(std::abs(b.region[3] - b.integral), 0.5);
  // So the gap is the displacements from the ellipses: -11.30 points measured.
  EXPECT_LT(b.region[2] - b.region[3], -10.0);
}

TEST(ArmVolumeBudget, TheElbowSectionLiesOnTheInnerSideOfTheJointCentredKey) {
  REQUIRE_SHARED_MALE();
  const float joint_centred = elbow_section_offset(male);
  const float section_centred = elbow_section_offset(section_centred_male(male));
  std::printf(
      "elbow section centroid on the inner side of its key: %.2f cm (key at the joint), "
      "%.2f cm (key at the section centroid)\n",
      100 * joint_centred, 100 * section_centred);
  // Measured 2.2 cm: turning about the joint, the bend sweeps this first moment of the section
  // (~60 cm² × ~1 cm averaged over the two bent spans × 2.6 rad ≈ 6.8 % of the arm) to the
  // inner side, which the ellipse integral cannot see (-6.3 % measured without correction).
  EXPECT_GT(joint_centred, 0.015f);
  EXPECT_LT(std::abs(section_centred), 0.003f);  // 0.0 measured: the fit's own centroid
}

TEST(ArmVolumeBudget, SectionCentredJointKeysCloseTheGap) {
  REQUIRE_SHARED_MALE();
  const Budget b = budget(section_centred_male(male), 150.0f, paper_correction());
  // Measured: integral +0.00, actual +1.46, sweep only +1.46, without c +1.47, on the
  // ellipses +1.06: the displacements add 0.4 points instead of -11.30.
  EXPECT_LT(std::abs(b.integral), 0.5);
  EXPECT_LT(std::abs(b.region[2] - b.region[3]), 1.0);
  EXPECT_LT(std::abs(b.region[0]), 2.0);  // the bound on the closed region
}

// The negative part of the signed swept volume, ∫ a b ρ min(0, <N, ∂S/∂t>) dρ dθ dt over the
// solid ellipses (where the sweep runs backwards through itself: the inner fold of a bend), and
// the positive part; midpoint rule, ∂S/∂t by central differences.
void swept_parts(const Sweep& sweep, double* negative, double* positive) {
  constexpr int kT = 1500, kRho = 8, kTheta = 48;
  constexpr float kH = 1e-4f;
  *negative = *positive = 0.0;
  for (int i = 0; i < kT; ++i) {
    const float t = (i + 0.5f) / kT;
    const SweepFrame before = sweep.frame(t - kH), at = sweep.frame(t), after = sweep.frame(t + kH);
    for (int r = 0; r < kRho; ++r) {
      const float rho = (r + 0.5f) / kRho;
      for (int j = 0; j < kTheta; ++j) {
        const float theta = 2.0f * std::numbers::pi_v<float> * (j + 0.5f) / kTheta;
        auto point = [&](const SweepFrame& f) {
          return f.centre + f.rotation * glm::vec3(rho * f.a * std::cos(theta),
                                                   rho * f.b * std::sin(theta), 0.0f);
        };
        const double speed = glm::dot(at.rotation[2], (point(after) - point(before)) / (2.0f * kH));
        const double weight =
            double(at.a) * at.b * rho * 2.0 * std::numbers::pi / (kRho * kTheta * kT);
        (speed < 0.0 ? *negative : *positive) += speed * weight;
      }
    }
  }
}

TEST(ArmVolumeBudget, CorrectingAcrossTheBendPlaneFoldsLess) {
  REQUIRE_SHARED_MALE();
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  double fold[2];
  for (int i = 0; i < 2; ++i) {
    Deformer deformer(male);
    deformer.set_options(paper_correction(i == 0 ? 10.0f : -1.0f));
    test::deformed(deformer, test::left_elbow_bent(male.model, 150.0f), DeformMethod::kSweep);
    const Sweep& sweep = deformer.sweep_poser().sweep(arm);
    double negative, positive;
    swept_parts(sweep, &negative, &positive);
    const double integral = sweep_volume(sweep);
    // The parts add up to the exact integral: the quadrature is good to 0.2 % (0.01 measured).
    EXPECT_NEAR(negative + positive, integral, 2e-3 * integral);
    fold[i] = 100 * negative / integral;
  }
  std::printf(
      "elbow 150°, negative swept volume (inner fold), %% of I: %.2f correcting across "
      "the bend plane only, %.2f correcting both half-axes\n",
      fold[0], fold[1]);
  // Measured -7.9 % against -10.0 %: growing the half-axis in the bend plane pushes the inner
  // side further past the bend's centre.
  EXPECT_GT(fold[0], fold[1] + 1.0);
}

}  // namespace
}  // namespace sweepd::deform
