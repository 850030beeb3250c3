// Volume preservation (paper §4.4) on the shared male: the elbow bent 0→150° keeps both the
// arm sweep's integral (the paper's correction) and the closed arm region's mesh volume, with
// LBS, DQS and uncorrected sweeps reported beside them; the rest pose is untouched; the
// correction starts on the elbow key, grows only its half-axis across the bend plane, honours
// I_C (the folding features' measured volume change), and leaves parts that are off alone.
#include "deform/volume/volume_preservation.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "deform/sweep/swept_volume.h"
#include "mannequin/mannequin.h"
#include "metrics/quality_metrics.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// Volume preservation on a test's jobs: alone (the paper's correction, I_C = 0), or with folding
// and protrusion (I_C: the volume they measure, deform/job/deform_job.h).
void preserving(test::Posing& posing, bool folding = false) {
  posing.features.volume = true;
  posing.features.folding = posing.features.protrusion = folding;
}

// One row per elbow angle 0, 10, …, 150°: the arm sweep's integral against rest and against
// its target, and the closed arm region's mesh volume against rest: the plain sweep (preserve
// false), the paper's correction, or the correction with folding and protrusion.
struct ElbowRow {
  int degrees;
  double integral, integral_vs_target, mesh;
};
std::vector<ElbowRow> bend_left_elbow(const BoundModel& male, bool preserve, bool folding = false) {
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  test::Posing deformer(male);
  if (preserve) preserving(deformer, folding);
  PartVolumeRegions regions(male);
  const double rest_mesh = regions.volume(arm, male.model.positions);
  const double rest_sweep = deformer.runtime.rest_volumes()[arm];
  std::vector<ElbowRow> rows;
  for (int degrees = 0; degrees <= 150; degrees += 10) {
    const auto positions =
        test::deformed(deformer, test::left_elbow_bent(male.model, static_cast<float>(degrees)),
                       DeformMethod::kSweep);
    const double integral = sweep_volume(deformer.sweep_poser().sweep(arm));
    const double target = preserve ? deformer.context.volume_corrections()[arm].target : rest_sweep;
    rows.push_back({degrees, integral / rest_sweep - 1, integral / target - 1,
                    regions.volume(arm, positions) / rest_mesh - 1});
  }
  return rows;
}

// The elbow table on one binding of the male: the arm sweep's integral and the closed arm
// region's volume, % against rest, for the plain sweep, the paper's correction and the
// correction with folding and protrusion (target I0 − I_C), with LBS and DQS beside them.
struct ElbowTable {
  std::vector<ElbowRow> plain, paper, folded;
};
ElbowTable print_elbow_table(const BoundModel& male, const char* binding) {
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  ElbowTable table{bend_left_elbow(male, false), bend_left_elbow(male, true),
                   bend_left_elbow(male, true, true)};
  test::Posing skinning(male);
  PartVolumeRegions regions(male);
  const double rest_mesh = regions.volume(arm, male.model.positions);
  std::printf(
      "left elbow bent (%s), %% change against rest. integral: sweep, +volume (paper), "
      "+volume +folding | closed arm region: the same three, lbs, dqs\n",
      binding);
  for (std::size_t i = 0; i < table.plain.size(); ++i) {
    const Pose pose = test::left_elbow_bent(male.model, static_cast<float>(table.plain[i].degrees));
    const double lbs =
        regions.volume(arm, test::deformed(skinning, pose, DeformMethod::kLbs)) / rest_mesh - 1;
    const double dqs =
        regions.volume(arm, test::deformed(skinning, pose, DeformMethod::kDqs)) / rest_mesh - 1;
    std::printf("%4d  %+7.2f %+7.2f %+7.2f | %+7.2f %+7.2f %+7.2f %+7.2f %+7.2f\n",
                table.plain[i].degrees, 100 * table.plain[i].integral,
                100 * table.paper[i].integral, 100 * table.folded[i].integral,
                100 * table.plain[i].mesh, 100 * table.paper[i].mesh, 100 * table.folded[i].mesh,
                100 * lbs, 100 * dqs);
  }
  return table;
}

double worst(const std::vector<ElbowRow>& rows, double ElbowRow::*field) {
  double result = 0.0;
  for (const ElbowRow& row : rows) result = std::max(result, std::abs(row.*field));
  return result;
}

TEST(VolumePreservation, PaperCorrectionKeepsTheArmIntegralAndItsClosedRegionAtRest) {
  REQUIRE_SHARED_MALE();
  const ElbowTable table = print_elbow_table(male, "the default binding");
  // Measured: integral within 0.01 % at every angle, region +1.64 % at 150° (+1.20 % at 120°,
  // +0.68 % at 90°; LBS -7.68 %, DQS -10.59 % at 150°). The bounds: ±0.5 % and ±2 %.
  EXPECT_LE(worst(table.paper, &ElbowRow::integral), 0.005);
  EXPECT_LE(worst(table.paper, &ElbowRow::mesh), 0.02);
  // With folding and protrusion the integral meets I0 − I_C instead (I_C: the volume they
  // measure, negative: folding takes away the skin that went through itself). That change is
  // large — the arm's at 150° is −11 % of I0 — so the integral grows by as much (+10.4 %
  // measured at 150°, +30.5 % at 120° where the 3 fixed-point rounds do not settle: a larger
  // arm folds more) and the closed region is not held to ±2 % (+16.6 % at 120°, +0.6 % at
  // 150°); see deform/README.md. What the job guarantees is the target, within the tolerance.
  EXPECT_LE(worst(table.folded, &ElbowRow::integral_vs_target), 0.005);
  // Uncorrected, the bend changes the volume, so the correction has something to do: the
  // sweep loses up to 3.5 % of the integral at turns up to 100° (a flexion of 146°; LBS loses
  // 7.6 % of the region), and past that the mitred elbow key (deform/posing/key_posing.h) gains,
  // +13.3 % at the 150° turn, a 196° flexion no arm reaches. The elbow's ellipse sits on its
  // section (KeyEllipse::offset), so the integral follows the closed region within 2 points.
  EXPECT_GT(std::abs(table.plain.back().integral), 0.05);
  for (const ElbowRow& row : table.plain)
    EXPECT_NEAR(row.integral, row.mesh, 0.02) << row.degrees << "°";
}

TEST(VolumePreservation, AtTheBentElbowOnlyTheHalfAxisAcrossTheBendPlaneIsCorrected) {
  REQUIRE_SHARED_MALE();
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  test::Posing plain(male), corrected(male);
  preserving(corrected);
  const Pose pose = test::left_elbow_bent(male.model, 120.0f);
  test::deformed(plain, pose, DeformMethod::kSweep);
  test::deformed(corrected, pose, DeformMethod::kSweep);
  const int elbow = corrected.context.volume_corrections()[arm].most_turned_key;
  const Sweep& before = plain.sweep_poser().sweep(arm);
  const Sweep& after = corrected.sweep_poser().sweep(arm);
  const glm::mat3 frame = after.rotation(static_cast<float>(after.parameters()[elbow]));
  const glm::vec3 axis = test::left_elbow_flexion_axis(male.model);
  // The half-axis whose direction is more nearly along the flexion axis is corrected; the
  // other, in the bend plane, keeps its posed control value exactly.
  const bool alpha_across = std::abs(glm::dot(frame[0], axis)) > std::abs(glm::dot(frame[1], axis));
  const double across = alpha_across ? after.alpha()[elbow] / before.alpha()[elbow]
                                     : after.beta()[elbow] / before.beta()[elbow];
  const double in_plane = alpha_across ? after.beta()[elbow] / before.beta()[elbow]
                                       : after.alpha()[elbow] / before.alpha()[elbow];
  std::printf("elbow key at 120°: across the bend plane x%.3f, in it x%.3f\n", across, in_plane);
  // x0.943 measured: at this 120° turn (166° flexion) the mitred key gained 4.6 % of the
  // integral; either way the correction must move the half-axis across the bend plane.
  EXPECT_GT(std::abs(across - 1.0), 0.05);
  EXPECT_EQ(in_plane, 1.0);
}

// Turning the whole body bends nothing, so it changes no correction: the spine bent 30° forward,
// then the same with the root turned 90° about the vertical as well, give the same vertices
// turned with the root. The root's own turn used to count as the torso's largest bend, so the
// torso's correction grew the keys at the hips instead of those at the bent joint (4.6 cm off
// on the male here): with the clip's body turning, sweep+volume stretched an edge 6.98x over
// cmu_01_03 (every 10th frame; 3.66x before the torso's planes turned gradually), 2.90x now,
// about the plain sweep's 2.87x.
TEST(VolumePreservation, TurningTheWholeBodyChangesNoCorrection) {
  std::vector<std::pair<std::string, BoundModel>> bodies;
  const Model mannequin = mannequin::make_mannequin({.target_vertices = 8000});
  bodies.emplace_back("mannequin", bind(mannequin, detect_rig_map(mannequin.skeleton)));
  if (test::shared_male()) bodies.emplace_back("male", *test::shared_male());
  for (const auto& [name, bound] : bodies) {
    const int torso = test::sweep_of(bound, BodyPart::kTorso);
    const Skeleton& skeleton = bound.model.skeleton;
    const BodyAxes axes = rest_body_axes(bound.rig, skeleton.world_rest_matrices());
    test::Posing upright(bound), turned(bound);
    preserving(upright);
    preserving(turned);
    const Pose bent = test::spine_bent_forward(bound, 30.0f);
    Pose bent_and_turned = bent;
    turn_joint(skeleton, bent_and_turned, 0, axes.up, 90.0f);
    const std::vector<glm::vec3> a = test::deformed(upright, bent, DeformMethod::kSweep);
    const std::vector<glm::vec3> b = test::deformed(turned, bent_and_turned, DeformMethod::kSweep);
    const VolumeCorrection& ca = upright.context.volume_corrections()[torso];
    const VolumeCorrection& cb = turned.context.volume_corrections()[torso];
    std::printf("%s: torso correction from key %d (%d steps) upright, %d (%d steps) turned\n",
                name.c_str(), ca.most_turned_key, ca.iterations, cb.most_turned_key, cb.iterations);
    EXPECT_EQ(cb.most_turned_key, ca.most_turned_key) << name;
    EXPECT_NE(bound.sweeps[torso].anchors[ca.most_turned_key].joint, 0) << name;
    // The turn about the root's rest position; float rounding of the posing: within 1e-5 of
    // the body's height (measured below 2e-6).
    const glm::vec3 root(skeleton.world_rest_matrices()[0][3]);
    const glm::quat turn = glm::angleAxis(glm::radians(90.0f), glm::normalize(axes.up));
    float worst = 0.0f;
    for (std::size_t v = 0; v < a.size(); ++v)
      worst = std::max(worst, glm::distance(b[v], root + turn * (a[v] - root)));
    std::printf("%s: turned body's vertices within %.3g m of the upright ones turned\n",
                name.c_str(), worst);
    EXPECT_LT(worst, 1e-5f * 1.75f) << name;
  }
}

TEST(VolumePreservation, WithFoldingTheTargetIsI0MinusTheFeaturesMeasuredVolumeChange) {
  REQUIRE_SHARED_MALE();
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  const Pose pose = test::left_elbow_and_knee_flexed(male.model, 150.0f);
  // A stream: the second frame's I_C is what folding and protrusion measured in the first.
  test::Posing stream(male);
  preserving(stream, true);
  stream.options.volume_change = VolumeChangeSource::kPreviousFrame;
  test::deformed(stream, pose, DeformMethod::kSweep);
  const std::span<const double> now = stream.context.measured_volume_change();
  const std::vector<double> measured(now.begin(), now.end());
  EXPECT_NE(measured[arm], 0.0);  // the 150° elbow folds
  test::deformed(stream, pose, DeformMethod::kSweep);
  EXPECT_EQ(stream.report.rounds, 1);  // one deformation: I_C is known before it
  const std::span<const double> rest = stream.runtime.rest_volumes();
  for (std::size_t s = 0; s < male.sweeps.size(); ++s) {
    const VolumeCorrection& c = stream.context.volume_corrections()[s];
    if (!c.corrected) continue;
    EXPECT_EQ(stream.report.volume_change[s], measured[s]) << s;
    EXPECT_DOUBLE_EQ(c.target, rest[s] - measured[s]) << s;  // I0 − I_C, to the last bit
  }
  // A frame that stands alone: the fixed-point loop re-targets on what the features measured
  // in the round before, for at most 3 deformations.
  test::Posing alone(male);
  preserving(alone, true);
  test::deformed(alone, pose, DeformMethod::kSweep);
  const VolumeCorrection& c = alone.context.volume_corrections()[arm];
  std::printf(
      "150° elbow and knee: arm I_C %+.2f cm³ measured (%.3f %% of I0); standalone frame: %d "
      "deformations, I_C %+.2f cm³ targeted, %+.2f cm³ measured after\n",
      1e6 * measured[arm], 100 * measured[arm] / rest[arm], alone.report.rounds,
      1e6 * alone.report.volume_change[arm], 1e6 * alone.context.measured_volume_change()[arm]);
  EXPECT_GE(alone.report.rounds, 2);
  EXPECT_LE(alone.report.rounds, 3);
  EXPECT_DOUBLE_EQ(c.target, rest[arm] - alone.report.volume_change[arm]);
  EXPECT_NE(alone.report.volume_change[arm], 0.0);
}

TEST(VolumePreservation, ReportsItsCostPerFrameAndBoundsItsWork) {
  REQUIRE_SHARED_MALE();
  const Pose pose = test::left_elbow_bent(male.model, 120.0f);
  std::vector<glm::vec3> positions(male.model.vertex_count());
  double milliseconds[3];
  int rounds = 0, most_steps = 0;
  for (int i = 0; i < 3; ++i) {
    test::Posing deformer(male);  // plain sweep, + volume, + volume with folding, protrusion
    if (i > 0) preserving(deformer, i == 2);
    Pose copy = pose;
    deformer.deform(copy, DeformMethod::kSweep, positions, {});  // warm
    constexpr int kFrames = 10;
    const auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < kFrames; ++f) {
      copy = pose;
      deformer.deform(copy, DeformMethod::kSweep, positions, {});
    }
    milliseconds[i] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count() /
        kFrames;
    if (i == 2) {
      rounds = deformer.report.rounds;
      for (const VolumeCorrection& c : deformer.context.volume_corrections())
        most_steps = std::max(most_steps, c.iterations);
    }
  }
  std::printf(
      "per frame, one thread: sweep %.2f ms, +volume (paper) %.2f ms, "
      "+volume +folding +protrusion %.2f ms; %d deformations, at most %d update steps a sweep\n",
      milliseconds[0], milliseconds[1], milliseconds[2], rounds, most_steps);
  // The cost in work rather than wall-clock time (which depends on the machine's load): a
  // standalone frame deforms at most fixed_point_rounds (3) times; each correction stops on its
  // tolerance before max_iterations.
  EXPECT_LE(rounds, DeformJobOptions{}.fixed_point_rounds);
  EXPECT_LT(most_steps, VolumePreservationOptions{}.max_iterations);
}

TEST(VolumePreservation, RestPoseIsLeftExactlyAsItWas) {
  REQUIRE_SHARED_MALE();
  test::Posing plain(male), corrected(male);
  preserving(corrected);
  const Pose rest = rest_pose(male.model.skeleton);
  const auto a = test::deformed(plain, rest, DeformMethod::kSweep);
  const auto b = test::deformed(corrected, rest, DeformMethod::kSweep);
  // At rest I = I0 to quadrature rounding, so no step is taken and the output is bit-identical.
  for (const VolumeCorrection& c : corrected.context.volume_corrections())
    EXPECT_EQ(c.iterations, 0);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)));
}

TEST(VolumePreservation, StartsOnTheElbowKeyAndReachesATargetLoweredByTheAddedVolume) {
  REQUIRE_SHARED_MALE();
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  test::Posing corrected(male);
  preserving(corrected);  // no folding: I_C is the input alone
  std::vector<double> added(male.sweeps.size(), 0.0);
  const double rest = corrected.runtime.rest_volumes()[arm];
  added[arm] = 0.03 * rest;  // e.g. a bulge elsewhere adds 3 % of the arm
  corrected.options.added_volume = added;
  corrected.options.volume.tolerance = 1e-4;
  const DeformJobOptions& options = corrected.options;
  test::deformed(corrected, test::left_elbow_bent(male.model, 120.0f), DeformMethod::kSweep);
  const VolumeCorrection& c = corrected.context.volume_corrections()[arm];
  const KeyAnchor& anchor = male.sweeps[arm].anchors[c.most_turned_key];
  EXPECT_EQ(anchor.joint, male.rig.left_arm.lower);
  EXPECT_TRUE(anchor.is_joint_key());
  EXPECT_NEAR(c.target, 0.97 * rest, 1e-12 * rest);
  // The loop stops once within the tolerance (1e-4 of I0), well before max_iterations.
  EXPECT_LT(std::abs(c.after - c.target), 1e-4 * rest);
  EXPECT_LT(c.iterations, options.volume.max_iterations);
  EXPECT_NEAR(sweep_volume(corrected.sweep_poser().sweep(arm)), c.after, 1e-12 * rest);
}

TEST(VolumePreservation, PartsThatAreOffAreNotCorrected) {
  REQUIRE_SHARED_MALE();
  test::Posing corrected(male);
  preserving(corrected);
  corrected.options.volume.arms = false;
  const DeformJobOptions& options = corrected.options;
  test::deformed(corrected, test::left_elbow_bent(male.model, 120.0f), DeformMethod::kSweep);
  const int arm = test::sweep_of(male, BodyPart::kLeftArm);
  const VolumeCorrection& c = corrected.context.volume_corrections()[arm];
  EXPECT_FALSE(c.corrected);
  EXPECT_EQ(c.iterations, 0);
  EXPECT_FALSE(
      corrected.context.volume_corrections()[test::sweep_of(male, BodyPart::kNeck)].corrected);
  EXPECT_TRUE(preserves_volume(BodyPart::kTorso, options.volume));
  EXPECT_FALSE(preserves_volume(BodyPart::kHead, options.volume));
}

TEST(VolumePreservation, RejectsAddedVolumesOfTheWrongSize) {
  REQUIRE_SHARED_MALE();
  test::Posing corrected(male);
  preserving(corrected);
  const std::vector<double> added = {1.0};
  corrected.options.added_volume = added;
  Pose pose = rest_pose(male.model.skeleton);
  std::vector<glm::vec3> positions(male.model.vertex_count());
  EXPECT_THROW(corrected.deform(pose, DeformMethod::kSweep, positions, {}), std::invalid_argument);
}

}  // namespace
}  // namespace sweepd::deform
