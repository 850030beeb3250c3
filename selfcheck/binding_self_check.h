// The binding's self-check (issue 47 item 3, DESIGN "never worse than skinning"): after bind(),
// the body is played through the peaks of its own range of motion (motion/range_of_motion.h,
// one pose per move: hip flexion 130°, deep squat, elbow 150°, ...) with the sweep, LBS and DQS,
// and each body region is judged as `sweepctl check` and the corpus gate judge it
// (metrics::compare_with_skinning, tolerance 1.02): the largest length ratio l / l_rest of its
// swept edges against the better baseline's, and its swept triangles that flip.
//
// check_binding
//   Inputs:  bound (bind's output), poses (range_of_motion_peaks(bound), or any poses with names)
//   Output:  BindingVerdict: one RegionVerdict per body region (metrics::label_regions' order):
//            how many poses were worse, and at the worst one (largest stretch excess) the two
//            ratios, the better baseline's name and the pose's name.
//   Cost:    per pose, one sweep, one LBS and one DQS deformation and three SweptStretchMeter
//            passes: on the shared male (14.5k vertices) about 1 ms a pose.
// self_check_warnings: one sentence per region still worse, naming the region, both ratios, the
//   method and the move ("left leg: the sweep stretches an edge 1.43x where DQS stretches it
//   1.31x (hip flexion 130°)").
#pragma once

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/binding/bound_model.h"
#include "deform/model/pose.h"
#include "metrics/swept_stretch_meter.h"

namespace sweepd::selfcheck {

// Which self-check a stored verdict came from: raised whenever the poses (the range of motion's
// moves) or the judgement (compare_with_skinning, the warnings' wording) change, so that a
// verdict stored with an older one is checked again instead of read
// (server/models/self_check_sidecar.h). 3: a triangle counts in the region of each of its
// corners and flips against each corner's joint (metrics::triangle_regions, flipped_from_rest).
// 4: the torso's first key turns with the hips, not halfway to a root above them
// (deform/posing/key_posing.h): the same binding deforms otherwise on such rigs.
inline constexpr int kSelfCheckRevision = 4;

struct CheckPoses {
  std::vector<deform::Pose> poses;
  std::vector<std::string> names;  // one per pose: its range-of-motion move
};
// The peak of every range-of-motion move of this body's rig.
CheckPoses range_of_motion_peaks(const deform::BoundModel& bound);

struct RegionVerdict {
  deform::BodyPart region = deform::BodyPart::kNone;
  bool swept = false;    // the region has swept edges (else skinning alone moves it)
  int worse_poses = 0;   // poses where the sweep is worse than the better baseline
  // At the pose of the largest stretch excess (sweep / (1.02 x baseline); > 1 is worse):
  double excess = 0.0;
  double sweep = 1.0, baseline = 1.0;  // the two length ratios l / l_rest
  bool baseline_is_dqs = false;        // which baseline was the better one there
  int pose = -1;                       // index into CheckPoses, -1: none measured
  // The most swept triangles the sweep flipped beyond the better baseline's in one pose, and
  // that pose (-1: never more than the baseline).
  int extra_flipped = 0, flipped_pose = -1;
  bool worse() const { return worse_poses > 0; }
};

struct BindingVerdict {
  std::vector<RegionVerdict> regions;
  std::vector<std::string> pose_names;  // CheckPoses::names
  // Per pose (CheckPoses' index) and region: whether the sweep was worse there, and its
  // stretch excess.
  std::vector<std::vector<std::uint8_t>> worse_at;
  std::vector<std::vector<float>> excess_at;
  // And the sweep's swept edges longer than 1.3x their rest length there (SweptStretchMeter's
  // kStretchedEdge): how much of the region stretches.
  std::vector<std::vector<int>> stretched_at;
  int worse_regions() const;
  int worse_pairs() const;  // (pose, region) pairs worse than skinning: the measure
};

// The sweep's figures in every pose: per pose, one RegionFigures and one count of edges
// stretched beyond 1.3x per region (SweptStretchMeter::measure's).
struct SweepFigures {
  std::vector<std::vector<metrics::RegionFigures>> figures;
  std::vector<std::vector<int>> stretched;
};

// The poses' LBS and DQS figures, measured once; verdict() deforms a binding of the same model
// and blend shares (the same swept vertices: bind's, or one SweepRebinder changed) with the
// sweep and judges it against them. The parts below let a caller that changes a few vertices
// pose and measure those alone (adapt_binding).
class BindingChecker {
 public:
  BindingChecker(const deform::BoundModel& bound, const CheckPoses& poses);
  BindingVerdict verdict(const deform::BoundModel& bound) const;

  // What verdict() measures with: regions, and the vertices it reads.
  const metrics::SweptStretchMeter& meter() const { return meter_; }
  // The sweep's positions of `vertices` (model indices) in every pose: per pose, in their order
  // (deform::bound_part: those vertices posed alone).
  std::vector<std::vector<glm::vec3>> sweep_positions(
      const deform::BoundModel& bound, std::span<const std::uint32_t> vertices) const;
  // The same in `order` (pose indices): each(pose, positions) returns false to stop there, and
  // pose_each then returns false. each is called for two poses at once (on two threads), so it
  // may write only what belongs to its pose; the pose after one that stopped may be called too.
  bool pose_each(const deform::BoundModel& bound, std::span<const std::uint32_t> vertices,
                 std::span<const int> order,
                 const std::function<bool(int, std::span<const glm::vec3>)>& each) const;
  // `part` (meter() or one of its parts) measured on those positions of its vertices.
  SweepFigures measure(const metrics::SweptStretchMeter& part,
                       const std::vector<std::vector<glm::vec3>>& positions) const;
  std::span<const glm::mat4> world(int pose) const { return world_[pose]; }
  // The sweep's figures of one region in one pose against the baselines'.
  metrics::SkinningComparison compare(int pose, int region,
                                      const metrics::RegionFigures& sweep) const;
  // The sweep's figures of the whole meter, against the baselines'.
  BindingVerdict judge(const SweepFigures& sweep) const;

 private:
  metrics::SweptStretchMeter meter_;
  CheckPoses poses_;
  std::vector<std::vector<glm::mat4>> world_, skinning_;          // per pose
  std::vector<std::vector<metrics::RegionFigures>> lbs_, dqs_;   // per pose
};

BindingVerdict check_binding(const deform::BoundModel& bound, const CheckPoses& poses);

// adapt_binding: for each sweep whose own regions (its part, the skinned part at its end) lose
// to skinning, fits it again with the other link key count (2 where it has 1, bind's default,
// else 1), the other orientation curve, and both (deform::SweepRebinder), and judges each candidate on every pose.
// A candidate is acceptable when it leaves fewer (pose, region) pairs worse over the whole body,
// makes no (pose, region) pair worse that was not, raises no pair's stretch excess (sweep /
// 1.02x the better baseline) above both its current one and 0.9, and stretches no more edges
// beyond 1.3x their rest length (summed over the poses). A choice that lowers the worst edge by
// spreading the stretch over more of the limb (1 link key on a MakeHuman thigh at the 150° knee)
// is not better; one that brings a pair it wins nearer to losing is not kept either: judged on
// the peaks alone, the shared male's arms on the smooth curve won 10 pairs there and lost 5 more
// cmu_01_03 frames. The best acceptable one (fewer pairs; as many, a smaller summed excess) is
// kept and recorded in BoundSweep::choice; else the sweep stays as bound. Sweeps are tried in
// order, each from the previous ones' result.
// Cost: a candidate is first judged on a probe: the edges and triangles around each touched
// region's longest edge on the sweep in every pose (as bound, and where an earlier candidate
// lost), their vertices alone bound and posed. Its figures are some of the whole's, and the
// ones judged (a region's largest ratio, its flipped count) only grow with more items, so a
// pair the probe refuses the whole refuses too: the same choices, at a few hundred vertices a
// candidate. A candidate the probe passes is bound whole; it changes the vertices on its sweep
// alone, so only they and their neighbours are posed and only the edges and triangles they
// touch are measured again (the rest from the body's positions kept per pose); its poses are
// measured nearest to losing first, and it stops at the first pair it may not have (each
// pose's figures beside the sweep measured when a candidate first reaches it); two poses are
// judged at a time. The self-check with the adaptation costs about 2.3x bind's own CPU time
// (72k mannequin at load 6: 212 ms bind, 697 ms in all; docs/performance.md): a third the
// candidates (most of it the one the probe passes), a third the meter and the baselines'
// figures, a fifth the body's figures.
struct Adaptation {
  BindingVerdict before;  // checker.verdict(bound) as bound
  BindingVerdict after;   // the same after the adaptation
};
Adaptation adapt_binding(deform::BoundModel& bound, const BindingChecker& checker);

// One line per sweep the self-check changed: its choice and the pairs before and after.
std::vector<std::string> adaptation_notes(const deform::BoundModel& bound);

// bind, then the self-check, and with `adapt` the adaptation: what sweepctl binds with.
struct CheckedBinding {
  deform::BoundModel bound;
  BindingVerdict before;   // the self-check of bind's own result
  BindingVerdict verdict;  // after the adaptation (without it: before)
  double bind_seconds = 0.0, check_seconds = 0.0;  // bind; the self-check and adaptation
};
CheckedBinding bind_checked(const deform::Model& model, const deform::RigMap& rig,
                            const deform::BindOptions& options = {}, bool adapt = false,
                            const deform::BindProgress& progress = {},
                            bool sweep_carried_ends = false);  // deform::bind's

std::vector<std::string> self_check_warnings(const BindingVerdict& verdict);

// The same warnings with their figures, for a client to read (protocol ModelInfo.bind_warnings):
// one per region still worse, in the verdict's region order; `text` is self_check_warnings'.
struct RegionWarning {
  std::string region;                 // deform::to_string of the body part: "left arm"
  int worse_poses = 0, pose_count = 0;
  // At the pose of the largest stretch excess; 0, 0, "" and "" when the region loses by
  // flipped triangles alone.
  double sweep = 0.0, baseline = 0.0;
  std::string baseline_name;          // "LBS" or "DQS"
  std::string pose;                   // that pose's move
  int extra_flipped = 0;              // RegionVerdict's; with flipped_pose "" when never more
  std::string flipped_pose;
  std::string text;
  bool operator==(const RegionWarning&) const = default;
};
std::vector<RegionWarning> region_warnings(const BindingVerdict& verdict);

}  // namespace sweepd::selfcheck
