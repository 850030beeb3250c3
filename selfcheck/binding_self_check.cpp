#include "selfcheck/binding_self_check.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/binding/bind.h"
#include "deform/blending/sweep_blending.h"
#include "deform/model/forward_kinematics.h"
#include "deform/posing/sweep_poser.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"

namespace sweepd::selfcheck {

CheckPoses range_of_motion_peaks(const deform::BoundModel& bound) {
  const deform::Skeleton& skeleton = bound.model.skeleton;
  motion::RangeOfMotion rom = motion::range_of_motion(skeleton, bound.rig);
  const motion::OwnSkeletonClip player(std::move(rom.clip), skeleton);
  CheckPoses poses;
  for (const motion::RomMove& move : rom.moves) {
    poses.poses.push_back(player.pose_at_frame(move.peak_frame));
    poses.names.push_back(move.name);
  }
  return poses;
}

int BindingVerdict::worse_regions() const {
  return static_cast<int>(std::count_if(regions.begin(), regions.end(),
                                        [](const RegionVerdict& r) { return r.worse(); }));
}

BindingChecker::BindingChecker(const deform::BoundModel& bound, const CheckPoses& poses)
    : meter_(bound), poses_(poses) {
  const deform::Model& model = bound.model;
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model.skeleton);
  world_.resize(poses.poses.size(), std::vector<glm::mat4>(model.skeleton.size()));
  skinning_.resize(poses.poses.size(), std::vector<glm::mat4>(model.skeleton.size()));
  // Skinning deforms the measured vertices alone (a head, hands and feet are most of a
  // MakeHuman body's vertices and are no edge of the verdict).
  deform::Model measured_part;
  measured_part.skeleton = model.skeleton;  // the skinning matrices' count (skinning_buffers_fit)
  for (const std::uint32_t v : meter_.vertices()) {
    measured_part.positions.push_back(model.positions[v]);
    measured_part.skin_joints.push_back(model.skin_joints[v]);
    measured_part.skin_weights.push_back(model.skin_weights[v]);
  }
  std::vector<glm::vec3> skinned(measured_part.positions.size());
  lbs_.resize(poses.poses.size());
  dqs_.resize(poses.poses.size());
  for (std::size_t p = 0; p < poses.poses.size(); ++p) {
    deform::forward_kinematics(model.skeleton, poses.poses[p], world_[p]);
    deform::skinning_matrices(world_[p], rest_inverse, skinning_[p]);
    deform::linear_blend_skinning(measured_part, skinning_[p], skinned, {});
    meter_.measure(skinned, world_[p], lbs_[p]);
    deform::dual_quaternion_skinning(measured_part, skinning_[p], skinned, {});
    meter_.measure(skinned, world_[p], dqs_[p]);
  }
}

BindingVerdict BindingChecker::verdict(const deform::BoundModel& bound) const {
  std::vector<int> every(poses_.poses.size());
  for (std::size_t p = 0; p < every.size(); ++p) every[p] = static_cast<int>(p);
  return verdict(bound, every);
}

BindingVerdict BindingChecker::verdict(const deform::BoundModel& bound,
                                       const std::vector<int>& poses) const {
  deform::SweepPoser poser(bound);
  std::vector<glm::vec3> positions(bound.model.vertex_count()), measured;
  std::vector<metrics::RegionFigures> sweep;
  std::vector<int> stretched;
  BindingVerdict verdict;
  verdict.pose_names = poses_.names;
  for (const deform::BodyPart region : meter_.regions())
    verdict.regions.push_back({.region = region});
  verdict.worse_at.resize(poses_.poses.size());
  verdict.excess_at.resize(poses_.poses.size());
  verdict.stretched_at.resize(poses_.poses.size());
  for (const int p : poses) {
    verdict.worse_at[p].assign(verdict.regions.size(), 0);
    verdict.excess_at[p].assign(verdict.regions.size(), 0.0f);
    poser.set_pose(world_[p]);
    poser.deform(skinning_[p], positions, {});
    meter_.gather(positions, measured);
    meter_.measure(measured, world_[p], sweep, stretched);
    verdict.stretched_at[p] = stretched;
    const std::vector<metrics::RegionFigures>& lbs = lbs_[p];
    const std::vector<metrics::RegionFigures>& dqs = dqs_[p];
    for (std::size_t r = 0; r < verdict.regions.size(); ++r) {
      const metrics::SkinningComparison c = metrics::compare_with_skinning(sweep[r], lbs[r], dqs[r]);
      if (!c.swept) continue;
      RegionVerdict& v = verdict.regions[r];
      v.swept = true;
      v.worse_poses += c.worse;
      verdict.worse_at[p][r] = c.worse;
      verdict.excess_at[p][r] = static_cast<float>(c.excess);
      if (v.pose < 0 || c.excess > v.excess) {
        v.excess = c.excess, v.sweep = c.sweep, v.baseline = c.baseline;
        v.baseline_is_dqs = dqs[r].swept_stretch < lbs[r].swept_stretch;
        v.pose = p;
      }
      const int extra =
          sweep[r].swept_flipped - std::min(lbs[r].swept_flipped, dqs[r].swept_flipped);
      if (extra > v.extra_flipped) v.extra_flipped = extra, v.flipped_pose = p;
    }
  }
  return verdict;
}

BindingVerdict check_binding(const deform::BoundModel& bound, const CheckPoses& poses) {
  return BindingChecker(bound, poses).verdict(bound);
}

namespace {

// A verdict's measure over some poses: the worse (pose, region) pairs, and their summed excess;
// beside it, the swept edges stretched beyond 1.3x.
struct Score {
  int pairs = 0;
  double excess = 0.0;
  long stretched = 0;
  // Fewer pairs; as many, a smaller summed excess.
  bool operator<(const Score& other) const {
    if (pairs != other.pairs) return pairs < other.pairs;
    return excess < other.excess - 1e-6;
  }
};

Score score(const BindingVerdict& verdict, const std::vector<int>& poses) {
  Score s;
  for (const int p : poses)
    for (std::size_t r = 0; r < verdict.worse_at[p].size(); ++r) {
      if (verdict.worse_at[p][r]) ++s.pairs, s.excess += verdict.excess_at[p][r];
      s.stretched += verdict.stretched_at[p][r];
    }
  return s;
}

std::vector<int> every_pose(const BindingVerdict& verdict) {
  std::vector<int> poses;
  for (std::size_t p = 0; p < verdict.worse_at.size(); ++p)
    if (!verdict.worse_at[p].empty()) poses.push_back(static_cast<int>(p));
  return poses;
}

// The regions sweep `part` reaches: its own, the skinned part at its end, and the torso it
// blends into; the torso's sweep reaches them all.
bool reaches(deform::BodyPart part, deform::BodyPart region) {
  return part == deform::BodyPart::kTorso || region == part || region == deform::BodyPart::kTorso ||
         (deform::end_part(part) != deform::BodyPart::kNone && region == deform::end_part(part));
}

// Whether sweep `part`'s own regions (its part and the skinned part at its end) lose anywhere.
bool sweep_loses(const BindingVerdict& verdict, deform::BodyPart part) {
  const deform::BodyPart end = deform::end_part(part);
  return std::any_of(verdict.regions.begin(), verdict.regions.end(), [&](const RegionVerdict& r) {
    return r.worse() && (r.region == part || (end != deform::BodyPart::kNone && r.region == end));
  });
}

// Whether every region `after` finds worse than skinning was worse `before` too.
bool no_region_newly_worse(const BindingVerdict& before, const BindingVerdict& after) {
  for (std::size_t r = 0; r < after.regions.size(); ++r)
    if (after.regions[r].worse() && !before.regions[r].worse()) return false;
  return true;
}

// The poses where a region sweep `part` reaches is worse, or within 10 % of it.
constexpr float kNearlyWorse = 0.9f;
std::vector<int> poses_at_stake(const BindingVerdict& verdict, deform::BodyPart part) {
  std::vector<int> poses;
  for (const int p : every_pose(verdict))
    for (std::size_t r = 0; r < verdict.regions.size(); ++r)
      if (reaches(part, verdict.regions[r].region) &&
          (verdict.worse_at[p][r] || verdict.excess_at[p][r] > kNearlyWorse)) {
        poses.push_back(p);
        break;
      }
  return poses;
}

}  // namespace

int BindingVerdict::worse_pairs() const { return score(*this, every_pose(*this)).pairs; }

BindingVerdict adapt_binding(deform::BoundModel& bound, const BindingChecker& checker,
                             BindingVerdict verdict) {
  std::optional<deform::SweepRebinder> rebinder;
  for (int s = 0; s < static_cast<int>(bound.sweeps.size()); ++s) {
    const deform::BodyPart part = bound.sweeps[s].part;
    if (!sweep_loses(verdict, part)) continue;
    if (!rebinder) rebinder.emplace(bound);
    const std::vector<int> at_stake = poses_at_stake(verdict, part);
    const deform::SweepChoice current = bound.sweeps[s].choice;
    const deform::OrientationCurveKind other =
        current.orientation_curve == deform::OrientationCurveKind::kLinear
            ? deform::OrientationCurveKind::kSmooth
            : deform::OrientationCurveKind::kLinear;
    const int fewer = current.keys_per_link == 1 ? 2 : 1;
    const deform::BoundSweep kept_sweep = bound.sweeps[s];
    const std::vector<deform::VertexBinding> kept_vertices = bound.vertices;
    Score best_score = score(verdict, at_stake);
    std::optional<deform::SweepChoice> best;
    for (const auto& [keys, curve] : {std::pair{fewer, current.orientation_curve},
                                      std::pair{current.keys_per_link, other},
                                      std::pair{fewer, other}}) {
      const deform::SweepChoice choice{
          .orientation_curve = curve,
          .keys_per_link = keys,
          .origin = deform::SweepChoiceOrigin::kSelfCheck,
          .worse_before = static_cast<std::uint32_t>(verdict.worse_pairs())};
      try {
        rebinder->rebind(bound, s, choice);
      } catch (const std::invalid_argument&) {
        continue;  // this choice cannot be fitted: not a candidate
      }
      const Score tried = score(checker.verdict(bound, at_stake), at_stake);
      if (tried < best_score && tried.stretched <= best_score.stretched)
        best_score = tried, best = choice;
      bound.sweeps[s] = kept_sweep;
      bound.vertices = kept_vertices;
    }
    if (!best) continue;
    rebinder->rebind(bound, s, *best);
    BindingVerdict tried = checker.verdict(bound);  // every pose: better over the whole body?
    if (tried.worse_pairs() < verdict.worse_pairs() && no_region_newly_worse(verdict, tried) &&
        score(tried, every_pose(tried)).stretched <= score(verdict, every_pose(verdict)).stretched) {
      verdict = std::move(tried);
      bound.sweeps[s].choice.worse_after = static_cast<std::uint32_t>(verdict.worse_pairs());
    } else {
      bound.sweeps[s] = kept_sweep;
      bound.vertices = kept_vertices;
    }
  }
  return verdict;
}

std::vector<std::string> adaptation_notes(const deform::BoundModel& bound) {
  std::vector<std::string> notes;
  for (const deform::BoundSweep& sweep : bound.sweeps) {
    const deform::SweepChoice& c = sweep.choice;
    if (c.origin != deform::SweepChoiceOrigin::kSelfCheck) continue;
    char text[240];
    std::snprintf(text, sizeof text,
                  "%s sweep: %d link key%s per link, %s orientation curve (worse than skinning "
                  "in %u (pose, region) pairs before, %u after)",
                  deform::to_string(sweep.part), c.keys_per_link, c.keys_per_link == 1 ? "" : "s",
                  c.orientation_curve == deform::OrientationCurveKind::kSmooth ? "smooth"
                                                                                : "linear",
                  c.worse_before, c.worse_after);
    notes.push_back(text);
  }
  return notes;
}

CheckedBinding bind_checked(const deform::Model& model, const deform::RigMap& rig,
                            const deform::BindOptions& options, bool adapt,
                            const deform::BindProgress& progress) {
  const auto started = std::chrono::steady_clock::now();
  CheckedBinding checked;
  checked.bound = deform::bind(model, rig, options, progress);
  const auto bound_at = std::chrono::steady_clock::now();
  const BindingChecker checker(checked.bound, range_of_motion_peaks(checked.bound));
  checked.before = checker.verdict(checked.bound);
  checked.verdict =
      adapt ? adapt_binding(checked.bound, checker, checked.before) : checked.before;
  const auto done = std::chrono::steady_clock::now();
  checked.bind_seconds = std::chrono::duration<double>(bound_at - started).count();
  checked.check_seconds = std::chrono::duration<double>(done - bound_at).count();
  return checked;
}

std::vector<RegionWarning> region_warnings(const BindingVerdict& verdict) {
  std::vector<RegionWarning> warnings;
  for (const RegionVerdict& v : verdict.regions) {
    if (!v.worse()) continue;
    RegionWarning w;
    w.region = deform::to_string(v.region);
    w.worse_poses = v.worse_poses;
    w.pose_count = static_cast<int>(verdict.pose_names.size());
    char text[320];
    int n = std::snprintf(text, sizeof text, "%s: worse than skinning in %d of %d poses",
                          w.region.c_str(), w.worse_poses, w.pose_count);
    if (v.excess > 1.0) {
      w.sweep = v.sweep, w.baseline = v.baseline;
      w.baseline_name = v.baseline_is_dqs ? "DQS" : "LBS";
      w.pose = verdict.pose_names[v.pose];
      n += std::snprintf(text + n, sizeof text - n,
                         "; the sweep stretches an edge %.2fx where %s stretches it %.2fx (%s)",
                         w.sweep, w.baseline_name.c_str(), w.baseline, w.pose.c_str());
    }
    if (v.flipped_pose >= 0) {
      w.extra_flipped = v.extra_flipped;
      w.flipped_pose = verdict.pose_names[v.flipped_pose];
      std::snprintf(text + n, sizeof text - n, "; %d more triangle%s flipped than skinning (%s)",
                    w.extra_flipped, w.extra_flipped == 1 ? "" : "s", w.flipped_pose.c_str());
    }
    w.text = text;
    warnings.push_back(std::move(w));
  }
  return warnings;
}

std::vector<std::string> self_check_warnings(const BindingVerdict& verdict) {
  std::vector<std::string> texts;
  for (RegionWarning& warning : region_warnings(verdict)) texts.push_back(std::move(warning.text));
  return texts;
}

}  // namespace sweepd::selfcheck
