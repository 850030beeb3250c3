// The binding's self-check (selfcheck/binding_self_check.h): its lean meter gives the figures
// RegionMeter gives, its verdict is the one `sweepctl check` reaches on the same poses, it says
// so when a region is spoiled on purpose, and its warnings name the region, the two ratios, the
// baseline and the move. On the 6k mannequin (a few hundred ms in Release).
#include "selfcheck/binding_self_check.h"

#include <gtest/gtest.h>

#include "deform/binding/bind.h"
#include "mannequin/mannequin.h"
#include "metrics/region_quality.h"
#include "metrics/swept_stretch_meter.h"
#include "tests/deform/shared_male.h"

namespace sweepd::selfcheck {
namespace {

using deform::BodyPart;
using deform::DeformMethod;

const deform::BoundModel& mannequin_binding() {
  static const deform::BoundModel bound = [] {
    const deform::Model model = mannequin::make_mannequin({.target_vertices = 6000});
    return deform::bind(model, deform::detect_rig_map(model.skeleton));
  }();
  return bound;
}

// The figures RegionMeter measures, per pose, method and region: what `sweepctl check` and the
// corpus gate compare.
std::vector<std::vector<metrics::RegionFigures>> region_meter_figures(
    const deform::BoundModel& bound, deform::Pose pose) {
  deform::test::Posing posing(bound);
  const metrics::RegionMeter meter(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count());
  std::vector<std::vector<metrics::RegionFigures>> figures;
  for (const DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs}) {
    posing.deform(pose, method, positions);
    figures.push_back(meter.measure(positions, posing.world_pose()));
  }
  return figures;
}

TEST(SweptStretchMeter, GivesRegionMetersSweptFiguresOnTheRangeOfMotionPeaks) {
  const deform::BoundModel& bound = mannequin_binding();
  const CheckPoses poses = range_of_motion_peaks(bound);
  ASSERT_GE(poses.poses.size(), 40u) << "the range of motion has ~48 moves on a full rig";
  const metrics::SweptStretchMeter lean(bound);
  ASSERT_EQ(lean.regions(), metrics::RegionMeter(bound).regions());
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count()), measured;
  std::vector<metrics::RegionFigures> figures;
  // Every 10th peak (hips, knees, spine, neck, shoulders): within the test's second.
  for (std::size_t p = 0; p < poses.poses.size(); p += 10) {
    const auto expected = region_meter_figures(bound, poses.poses[p]);
    for (int m = 0; m < 3; ++m) {
      deform::Pose pose = poses.poses[p];
      posing.deform(pose, static_cast<DeformMethod>(m), positions);
      lean.gather(positions, measured);
      lean.measure(measured, posing.world_pose(), figures);
      for (std::size_t r = 0; r < figures.size(); ++r) {
        SCOPED_TRACE(poses.names[p] + ", " + deform::to_string(lean.regions()[r]));
        EXPECT_EQ(figures[r].swept, expected[m][r].swept);
        // Squared lengths and one square root against a ratio per edge: float roundings.
        EXPECT_NEAR(figures[r].swept_stretch, expected[m][r].swept_stretch, 1e-5);
        EXPECT_EQ(figures[r].swept_flipped, expected[m][r].swept_flipped);
      }
    }
  }
}

TEST(SweptStretchMeter, ItsPartsTouchingAVertexSetAndNotCombineIntoTheWhole) {
  const deform::BoundModel& bound = mannequin_binding();
  const metrics::SweptStretchMeter whole(bound);
  // The vertices on the left arm's sweep: what the adaptation re-binds.
  int arm = -1;
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (bound.sweeps[s].part == BodyPart::kLeftArm) arm = static_cast<int>(s);
  ASSERT_GE(arm, 0);
  std::vector<std::uint8_t> moving(bound.vertices.size(), 0);
  int on_arm = 0;
  for (std::size_t v = 0; v < bound.vertices.size(); ++v)
    for (int k = 0; k < deform::kSweepsPerVertex; ++k)
      if (bound.vertices[v].sweep[k] == arm) moving[v] = 1, ++on_arm;
  ASSERT_GT(on_arm, 100);
  const metrics::SweptStretchMeter touching = whole.part(moving, true);
  const metrics::SweptStretchMeter rest = whole.part(moving, false);
  const std::vector<std::uint8_t> touched = whole.regions_touched(moving);
  EXPECT_LT(touching.vertices().size(), whole.vertices().size() / 2);
  EXPECT_LT(rest.vertices().size(), whole.vertices().size());
  EXPECT_EQ(touching.regions(), whole.regions());
  // The arm, the hand at its end and the torso it blends into; not the legs.
  for (std::size_t r = 0; r < whole.regions().size(); ++r) {
    const BodyPart region = whole.regions()[r];
    if (region == BodyPart::kLeftArm || region == BodyPart::kTorso) {
      EXPECT_TRUE(touched[r]);
    }
    if (region == BodyPart::kLeftLeg || region == BodyPart::kRightLeg) {
      EXPECT_FALSE(touched[r]);
    }
  }
  const CheckPoses poses = range_of_motion_peaks(bound);
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count()), measured;
  for (std::size_t p = 0; p < poses.poses.size(); p += 5) {
    deform::Pose pose = poses.poses[p];
    posing.deform(pose, DeformMethod::kSweep, positions);
    std::vector<metrics::RegionFigures> expected, figures, rest_figures;
    std::vector<int> expected_stretched, stretched, rest_stretched;
    whole.gather(positions, measured);
    whole.measure(measured, posing.world_pose(), expected, expected_stretched);
    touching.gather(positions, measured);
    touching.measure(measured, posing.world_pose(), figures, stretched);
    rest.gather(positions, measured);
    rest.measure(measured, posing.world_pose(), rest_figures, rest_stretched);
    metrics::SweptStretchMeter::combine(figures, stretched, rest_figures, rest_stretched);
    for (std::size_t r = 0; r < figures.size(); ++r) {
      SCOPED_TRACE(poses.names[p] + ", " + deform::to_string(whole.regions()[r]));
      EXPECT_EQ(figures[r].swept, expected[r].swept);
      if (!touched[r]) {  // in neither part: the rest values
        EXPECT_EQ(figures[r].swept_stretch, 1.0);
        EXPECT_EQ(figures[r].swept_flipped, 0);
        continue;
      }
      // The same edges and triangles, each measured once by one part: exactly the whole's.
      EXPECT_EQ(figures[r].swept_stretch, expected[r].swept_stretch);
      EXPECT_EQ(figures[r].swept_flipped, expected[r].swept_flipped);
      EXPECT_EQ(stretched[r], expected_stretched[r]);
    }
  }
}

// measure_two (the self-check's LBS and DQS at once) gives each set what measure gives it, to the
// bit: the verdicts compare those figures to the bit across changes.
TEST(SweptStretchMeter, MeasuringTwoSetsAtOnceGivesEachWhatMeasuringItAloneGives) {
  const deform::BoundModel& bound = mannequin_binding();
  const metrics::SweptStretchMeter meter(bound);
  const CheckPoses poses = range_of_motion_peaks(bound);
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count()), lbs, dqs;
  int differing = 0;
  for (std::size_t p = 0; p < poses.poses.size(); p += 3) {
    deform::Pose pose = poses.poses[p];
    posing.deform(pose, DeformMethod::kLbs, positions);
    meter.gather(positions, lbs);
    posing.deform(pose, DeformMethod::kDqs, positions);
    meter.gather(positions, dqs);
    std::vector<metrics::RegionFigures> lbs_alone, dqs_alone, lbs_both, dqs_both;
    meter.measure(lbs, posing.world_pose(), lbs_alone);
    meter.measure(dqs, posing.world_pose(), dqs_alone);
    meter.measure_two(lbs, dqs, posing.world_pose(), lbs_both, dqs_both);
    ASSERT_EQ(lbs_both.size(), lbs_alone.size());
    ASSERT_EQ(dqs_both.size(), dqs_alone.size());
    for (std::size_t r = 0; r < lbs_alone.size(); ++r) {
      SCOPED_TRACE(poses.names[p] + ", " + deform::to_string(meter.regions()[r]));
      EXPECT_EQ(lbs_both[r].swept, lbs_alone[r].swept);
      EXPECT_EQ(lbs_both[r].swept_stretch, lbs_alone[r].swept_stretch);
      EXPECT_EQ(lbs_both[r].swept_flipped, lbs_alone[r].swept_flipped);
      EXPECT_EQ(dqs_both[r].swept_stretch, dqs_alone[r].swept_stretch);
      EXPECT_EQ(dqs_both[r].swept_flipped, dqs_alone[r].swept_flipped);
      // Two different sets: LBS and DQS differ somewhere, or the test compares one set twice.
      differing += lbs_alone[r].swept_stretch != dqs_alone[r].swept_stretch;
    }
  }
  EXPECT_GT(differing, 10);
}

// longest_edge names the edge whose ratio l / l_rest is the region's stretch (the probe's seed:
// the edge a candidate most likely stretches past).
TEST(SweptStretchMeter, ItsLongestEdgeIsTheOneWhoseRatioIsTheRegionsStretch) {
  const deform::BoundModel& bound = mannequin_binding();
  const metrics::SweptStretchMeter meter(bound);
  const CheckPoses poses = range_of_motion_peaks(bound);
  deform::test::Posing posing(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count()), measured;
  int stretched_regions = 0;
  for (std::size_t p = 0; p < poses.poses.size(); p += 5) {
    deform::Pose pose = poses.poses[p];
    posing.deform(pose, DeformMethod::kSweep, positions);
    meter.gather(positions, measured);
    std::vector<metrics::RegionFigures> figures;
    meter.measure(measured, posing.world_pose(), figures);
    for (std::size_t r = 0; r < figures.size(); ++r) {
      SCOPED_TRACE(poses.names[p] + ", " + deform::to_string(meter.regions()[r]));
      const auto edge = meter.longest_edge(measured, static_cast<int>(r));
      if (!figures[r].swept) continue;
      ASSERT_TRUE(edge.has_value());
      if (figures[r].swept_stretch <= 1.0) continue;  // the figure's floor: no edge longer
      ++stretched_regions;
      const auto [a, b] = *edge;
      const double ratio = glm::length(glm::dvec3(positions[a] - positions[b])) /
                           glm::length(glm::dvec3(bound.model.positions[a] - bound.model.positions[b]));
      // The meter squares in float: a few float roundings apart.
      EXPECT_NEAR(ratio, figures[r].swept_stretch, 1e-5 * ratio);
    }
  }
  EXPECT_GT(stretched_regions, 10);
}

TEST(BindingSelfCheck, ReachesTheVerdictThatRegionMeterReachesOnTheSamePoses) {
  const deform::BoundModel& bound = mannequin_binding();
  const CheckPoses poses = range_of_motion_peaks(bound);
  // A sixth of the peaks (the test's time); the hips', knees' and elbows' moves among them.
  CheckPoses some;
  for (std::size_t p = 0; p < poses.poses.size(); p += 6) {
    some.poses.push_back(poses.poses[p]);
    some.names.push_back(poses.names[p]);
  }
  const BindingVerdict verdict = check_binding(bound, some);
  ASSERT_EQ(verdict.pose_names.size(), some.poses.size());
  std::vector<int> worse(verdict.regions.size(), 0);
  std::vector<double> excess(verdict.regions.size(), 0.0);
  for (const deform::Pose& pose : some.poses) {
    const auto f = region_meter_figures(bound, pose);
    for (std::size_t r = 0; r < worse.size(); ++r) {
      const metrics::SkinningComparison c = metrics::compare_with_skinning(f[0][r], f[1][r], f[2][r]);
      worse[r] += c.worse;
      excess[r] = std::max(excess[r], c.excess);
    }
  }
  for (std::size_t r = 0; r < worse.size(); ++r) {
    SCOPED_TRACE(deform::to_string(verdict.regions[r].region));
    EXPECT_EQ(verdict.regions[r].worse_poses, worse[r]);
    EXPECT_NEAR(verdict.regions[r].excess, excess[r], 1e-5);  // the meter's float roundings
  }
}

TEST(BindingSelfCheck, ARegionSpoiledOnPurposeIsWorseInEveryPoseAndNamed) {
  deform::BoundModel bound = mannequin_binding();
  CheckPoses poses = range_of_motion_peaks(bound);
  poses.poses.resize(8), poses.names.resize(8);
  const BindingVerdict before = check_binding(bound, poses);
  // Every other vertex the left arm's sweep alone moves turns 0.3 rad about the arm: its
  // edges stretch in every pose, the rest pose included, where skinning stretches none.
  int arm = -1;
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (bound.sweeps[s].part == BodyPart::kLeftArm) arm = static_cast<int>(s);
  ASSERT_GE(arm, 0);
  int spoiled = 0;
  for (std::size_t v = 0; v < bound.vertices.size(); v += 2) {
    deform::VertexBinding& b = bound.vertices[v];
    if (b.sweep[0] == arm && b.weight[0] == 1.0f) b.coordinate[0].theta += 0.3f, ++spoiled;
  }
  ASSERT_GT(spoiled, 100);
  const BindingVerdict after = check_binding(bound, poses);
  ASSERT_EQ(after.regions.size(), before.regions.size());
  for (std::size_t r = 0; r < after.regions.size(); ++r) {
    const RegionVerdict& v = after.regions[r];
    SCOPED_TRACE(deform::to_string(v.region));
    if (v.region == BodyPart::kLeftArm) {
      EXPECT_EQ(v.worse_poses, 8);
      // Many of its edges stretch beyond 1.3x now, in every pose (none of it at rest before).
      for (int p = 0; p < 8; ++p)
        EXPECT_GT(after.stretched_at[p][r], before.stretched_at[p][r] + 50) << p;
      // A 0.3 rad turn on a ~5 cm arm radius moves a vertex ~1.5 cm against edges of ~1 cm.
      EXPECT_GT(v.excess, 1.5);
    } else {
      // What the spoiled arm does not reach keeps its verdict (the left hand's edges by the
      // wrist touch the arm's vertices: left alone).
      if (v.region == BodyPart::kLeftHand || v.region == BodyPart::kTorso) continue;
      EXPECT_EQ(v.worse_poses, before.regions[r].worse_poses);
      EXPECT_DOUBLE_EQ(v.excess, before.regions[r].excess);
    }
  }
  const std::vector<std::string> warnings = self_check_warnings(after);
  ASSERT_FALSE(warnings.empty());
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.starts_with("left arm: worse than skinning in 8 of 8 poses; the sweep stretches");
  })) << warnings.front();
}

// Every other vertex on the left arm's sweep, the shoulder's blend included, turned 0.3 rad
// about the arm: every region the sweep touches stretches far more than as bound in every pose,
// and a re-fitted sweep binds them again, so a candidate must win everywhere it reaches.
int spoil_left_arm(deform::BoundModel& bound) {
  int arm = -1;
  for (std::size_t s = 0; s < bound.sweeps.size(); ++s)
    if (bound.sweeps[s].part == BodyPart::kLeftArm) arm = static_cast<int>(s);
  for (std::size_t v = 0; v < bound.vertices.size(); v += 2)
    for (int k = 0; k < deform::kSweepsPerVertex; ++k)
      if (bound.vertices[v].sweep[k] == arm) bound.vertices[v].coordinate[k].theta += 0.3f;
  return arm;
}

TEST(BindingSelfCheck, AdaptationKeepsOnlyChoicesThatLeaveFewerPairsWorseAndRecordsThem) {
  deform::BoundModel bound = mannequin_binding();
  const int arm = spoil_left_arm(bound);
  ASSERT_GE(arm, 0);
  CheckPoses poses = range_of_motion_peaks(bound);
  const BindingChecker checker(bound, poses);
  const Adaptation adaptation = adapt_binding(bound, checker);
  const BindingVerdict& before = adaptation.before;
  const BindingVerdict& after = adaptation.after;
  ASSERT_GT(before.worse_pairs(), 0);
  // The spoiled arm is fitted again: fewer pairs worse.
  EXPECT_EQ(bound.sweeps[arm].choice.origin, deform::SweepChoiceOrigin::kSelfCheck);
  EXPECT_LT(after.worse_pairs(), before.worse_pairs());
  // No pair's stretch excess rose where it was within 10 % of losing (kNearlyWorse), beyond
  // the meter's float roundings: a choice may not trade a pair for one it nearly loses.
  for (std::size_t p = 0; p < poses.poses.size(); ++p)
    for (std::size_t r = 0; r < after.regions.size(); ++r)
      EXPECT_LE(after.excess_at[p][r], std::max(before.excess_at[p][r], 0.9f) + 1e-4f)
          << poses.names[p] << ", " << deform::to_string(after.regions[r].region);
  // What it returns is what the adapted binding measures, pose by pose (it measured only what
  // each candidate changed).
  const BindingVerdict measured = checker.verdict(bound);
  EXPECT_EQ(measured.worse_at, after.worse_at);
  EXPECT_EQ(measured.stretched_at, after.stretched_at);
  // And what it started from is the binding's own verdict.
  deform::BoundModel spoiled = mannequin_binding();
  spoil_left_arm(spoiled);
  EXPECT_EQ(checker.verdict(spoiled).worse_at, before.worse_at);
  int adapted = 0;
  for (const deform::BoundSweep& sweep : bound.sweeps) {
    const deform::SweepChoice& c = sweep.choice;
    if (c.origin != deform::SweepChoiceOrigin::kSelfCheck) {
      EXPECT_EQ(c.keys_per_link, bound.options.intermediate_keys_per_link)  // bind's options
          << deform::to_string(sweep.part);
      continue;
    }
    ++adapted;
    SCOPED_TRACE(deform::to_string(sweep.part));
    EXPECT_LT(c.worse_after, c.worse_before);  // kept only when fewer pairs are worse
    EXPECT_TRUE(c.keys_per_link != bound.options.intermediate_keys_per_link ||
                c.orientation_curve != deform::OrientationCurveKind::kLinear);
    // The keys it was fitted with: joint keys plus keys_per_link per link.
    EXPECT_EQ(sweep.rest_keys.size(),
              sweep.chain.size() + (sweep.chain.size() - 1) * c.keys_per_link);
  }
  EXPECT_EQ(adapted, static_cast<int>(adaptation_notes(bound).size()));
  // No more edges stretch beyond 1.3x in all.
  long stretched_before = 0, stretched_after = 0;
  for (std::size_t p = 0; p < poses.poses.size(); ++p)
    for (std::size_t r = 0; r < before.regions.size(); ++r) {
      stretched_before += before.stretched_at[p][r];
      stretched_after += after.stretched_at[p][r];
    }
  EXPECT_LE(stretched_after, stretched_before);
  // No (pose, region) pair became worse than skinning.
  for (std::size_t p = 0; p < poses.poses.size(); ++p)
    for (std::size_t r = 0; r < after.regions.size(); ++r)
      EXPECT_TRUE(!after.worse_at[p][r] || before.worse_at[p][r])
          << poses.names[p] << ", " << deform::to_string(after.regions[r].region);
  EXPECT_GE(adapted, 1);
  // The adapted binding still reconstructs its rest pose (every vertex re-bound on its sweep).
  const std::vector<glm::vec3> rest = deform::rest_positions_from_binding(bound);
  float worst = 0.0f;
  for (std::size_t v = 0; v < rest.size(); ++v)
    worst = std::max(worst, glm::length(rest[v] - bound.model.positions[v]));
  EXPECT_LT(worst, 1e-4f) << "metres";
}

TEST(BindingSelfCheck, AWarningSaysTheRegionBothLengthRatiosTheBaselineAndTheMove) {
  BindingVerdict verdict;
  verdict.pose_names = {"rest", "hip flexion 130°", "knee flexion 150°"};
  verdict.regions.push_back({.region = BodyPart::kTorso, .swept = true});  // not worse: silent
  verdict.regions.push_back({.region = BodyPart::kLeftLeg,
                             .swept = true,
                             .worse_poses = 2,
                             .excess = 1.43 / (1.02 * 1.31),
                             .sweep = 1.43,
                             .baseline = 1.31,
                             .baseline_is_dqs = true,
                             .pose = 1,
                             .extra_flipped = 3,
                             .flipped_pose = 2});
  verdict.regions.push_back({.region = BodyPart::kRightArm,
                             .swept = true,
                             .worse_poses = 1,
                             .excess = 0.99,  // worse by flipped triangles alone
                             .sweep = 1.2,
                             .baseline = 1.19,
                             .pose = 2,
                             .extra_flipped = 1,
                             .flipped_pose = 2});
  EXPECT_EQ(verdict.worse_regions(), 2);
  const std::vector<std::string> warnings = self_check_warnings(verdict);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0],
            "left leg: worse than skinning in 2 of 3 poses; the sweep stretches an edge 1.43x "
            "where DQS stretches it 1.31x (hip flexion 130°); 3 more triangles flipped than "
            "skinning (knee flexion 150°)");
  EXPECT_EQ(warnings[1],
            "right arm: worse than skinning in 1 of 3 poses; 1 more triangle flipped than "
            "skinning (knee flexion 150°)");
}

}  // namespace
}  // namespace sweepd::selfcheck
