#include "selfcheck/binding_self_check.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "deform/baselines/dual_quaternion_skinning.h"
#include "deform/baselines/linear_blend_skinning.h"
#include "deform/binding/bind.h"
#include "deform/binding/bound_part.h"
#include "deform/blending/sweep_blending.h"
#include "deform/model/forward_kinematics.h"
#include "deform/posing/sweep_poser.h"
#include "deform/simd/vertex_blocks.h"
#include "motion/own_skeleton_clip.h"
#include "motion/range_of_motion.h"

namespace sweepd::selfcheck {

namespace {

// The threads the check's per-pose passes (skinning and measuring every pose, posing the body)
// run on: a pair, as bind's own vertex loop (deform::kBindThreads). Each pose is computed
// alone, so the figures do not depend on the count.
constexpr int kCheckThreads = deform::kBindThreads;

}  // namespace

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
  const deform::SkinningTable measured_table(measured_part);  // built once, for every pose
  lbs_.resize(poses.poses.size());
  dqs_.resize(poses.poses.size());
  deform::run_in_vertex_blocks(
      poses.poses.size(), kCheckThreads, [&](std::size_t begin, std::size_t end) {
        std::vector<glm::vec3> lbs(measured_part.positions.size()), dqs(lbs.size());
        for (std::size_t p = begin; p < end; ++p) {
          deform::forward_kinematics(model.skeleton, poses.poses[p], world_[p]);
          deform::skinning_matrices(world_[p], rest_inverse, skinning_[p]);
          deform::linear_blend_skinning(measured_table, skinning_[p], lbs, {});
          deform::dual_quaternion_skinning(measured_table, skinning_[p], dqs, {});
          meter_.measure_two(lbs, dqs, world_[p], lbs_[p], dqs_[p]);
        }
      });
}

BindingVerdict BindingChecker::verdict(const deform::BoundModel& bound) const {
  return judge(measure(meter_, sweep_positions(bound, meter_.vertices())));
}

std::vector<std::vector<glm::vec3>> BindingChecker::sweep_positions(
    const deform::BoundModel& bound, std::span<const std::uint32_t> vertices) const {
  std::vector<std::vector<glm::vec3>> positions(poses_.poses.size());
  if (vertices.empty()) return positions;
  const deform::BoundModel part = deform::bound_part(bound, vertices);
  const std::shared_ptr<const deform::SweepPoserTables> tables =
      deform::make_sweep_poser_tables(part);
  deform::run_in_vertex_blocks(
      positions.size(), kCheckThreads, [&](std::size_t begin, std::size_t end) {
        deform::SweepPoser poser(tables);  // one per thread: a poser holds its pose
        for (std::size_t p = begin; p < end; ++p) {
          positions[p].resize(vertices.size());
          poser.set_pose(world_[p]);
          poser.deform(skinning_[p], positions[p], {});
        }
      });
  return positions;
}

bool BindingChecker::pose_each(
    const deform::BoundModel& bound, std::span<const std::uint32_t> vertices,
    std::span<const int> order,
    const std::function<bool(int, std::span<const glm::vec3>)>& each) const {
  if (vertices.empty()) {
    const std::vector<glm::vec3> none;
    for (const int p : order)
      if (!each(p, none)) return false;
    return true;
  }
  const deform::BoundModel part = deform::bound_part(bound, vertices);
  const std::shared_ptr<const deform::SweepPoserTables> tables =
      deform::make_sweep_poser_tables(part);
  // kCheckThreads poses at a time, one poser each; a pose after one that stops is computed and
  // not looked at.
  std::vector<deform::SweepPoser> posers;
  posers.reserve(kCheckThreads);
  std::vector<std::vector<glm::vec3>> positions(kCheckThreads,
                                                std::vector<glm::vec3>(vertices.size()));
  for (int k = 0; k < kCheckThreads; ++k) posers.emplace_back(tables);
  std::vector<std::uint8_t> kept(kCheckThreads);
  for (std::size_t i = 0; i < order.size(); i += kCheckThreads) {
    const std::size_t n = std::min<std::size_t>(kCheckThreads, order.size() - i);
    deform::run_in_vertex_blocks(n, kCheckThreads, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        const int p = order[i + k];
        posers[k].set_pose(world_[p]);
        posers[k].deform(skinning_[p], positions[k], {});
        kept[k] = each(p, positions[k]);
      }
    });
    for (std::size_t k = 0; k < n; ++k)
      if (!kept[k]) return false;
  }
  return true;
}

metrics::SkinningComparison BindingChecker::compare(int pose, int region,
                                                    const metrics::RegionFigures& sweep) const {
  return metrics::compare_with_skinning(sweep, lbs_[pose][region], dqs_[pose][region]);
}

SweepFigures BindingChecker::measure(const metrics::SweptStretchMeter& part,
                                     const std::vector<std::vector<glm::vec3>>& positions) const {
  SweepFigures sweep;
  sweep.figures.resize(positions.size());
  sweep.stretched.resize(positions.size());
  deform::run_in_vertex_blocks(
      positions.size(), kCheckThreads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p)
          part.measure(positions[p], world_[p], sweep.figures[p], sweep.stretched[p]);
      });
  return sweep;
}

BindingVerdict BindingChecker::judge(const SweepFigures& sweep) const {
  BindingVerdict verdict;
  verdict.pose_names = poses_.names;
  for (const deform::BodyPart region : meter_.regions())
    verdict.regions.push_back({.region = region});
  verdict.stretched_at = sweep.stretched;
  for (std::size_t p = 0; p < poses_.poses.size(); ++p) {
    verdict.worse_at.emplace_back(verdict.regions.size(), 0);
    verdict.excess_at.emplace_back(verdict.regions.size(), 0.0f);
    const std::vector<metrics::RegionFigures>& figures = sweep.figures[p];
    const std::vector<metrics::RegionFigures>& lbs = lbs_[p];
    const std::vector<metrics::RegionFigures>& dqs = dqs_[p];
    for (std::size_t r = 0; r < verdict.regions.size(); ++r) {
      const metrics::SkinningComparison c =
          compare(static_cast<int>(p), static_cast<int>(r), figures[r]);
      if (!c.swept) continue;
      RegionVerdict& v = verdict.regions[r];
      v.swept = true;
      v.worse_poses += c.worse;
      verdict.worse_at[p][r] = c.worse;
      verdict.excess_at[p][r] = static_cast<float>(c.excess);
      if (v.pose < 0 || c.excess > v.excess) {
        v.excess = c.excess, v.sweep = c.sweep, v.baseline = c.baseline;
        v.baseline_is_dqs = dqs[r].swept_stretch < lbs[r].swept_stretch;
        v.pose = static_cast<int>(p);
      }
      const int extra =
          figures[r].swept_flipped - std::min(lbs[r].swept_flipped, dqs[r].swept_flipped);
      if (extra > v.extra_flipped) v.extra_flipped = extra, v.flipped_pose = static_cast<int>(p);
    }
  }
  return verdict;
}

BindingVerdict check_binding(const deform::BoundModel& bound, const CheckPoses& poses) {
  return BindingChecker(bound, poses).verdict(bound);
}

namespace {

// A verdict's measure: the worse (pose, region) pairs and their summed excess; beside it, the
// swept edges stretched beyond 1.3x.
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

Score score(const BindingVerdict& verdict) {
  Score s;
  for (std::size_t p = 0; p < verdict.worse_at.size(); ++p)
    for (std::size_t r = 0; r < verdict.worse_at[p].size(); ++r) {
      if (verdict.worse_at[p][r]) ++s.pairs, s.excess += verdict.excess_at[p][r];
      s.stretched += verdict.stretched_at[p][r];
    }
  return s;
}

// Whether sweep `part`'s own regions (its part and the skinned part at its end) lose anywhere.
bool sweep_loses(const BindingVerdict& verdict, deform::BodyPart part) {
  const deform::BodyPart end = deform::end_part(part);
  return std::any_of(verdict.regions.begin(), verdict.regions.end(), [&](const RegionVerdict& r) {
    return r.worse() && (r.region == part || (end != deform::BodyPart::kNone && r.region == end));
  });
}

// A candidate's measure in one (pose, region) pair may not exceed its current one, where that
// is at least this close to losing (stretch excess 0.9): a candidate that wins the peaks by
// trading a pair it wins for one it nearly loses made clips the range of motion does not hold
// worse (the shared male's arms on the smooth curve: cmu_01_03 703 → 708 worse pairs).
constexpr float kNearlyWorse = 0.9f;
constexpr float kSameExcess = 1e-4f;  // the meter's float roundings

// Whether a candidate's pair `tried` may replace the current one: not worse than skinning where
// it was not, and no larger stretch excess than the current one or kNearlyWorse, whichever is
// larger.
bool pair_acceptable(const BindingVerdict& current, int pose, int region,
                     const metrics::SkinningComparison& tried) {
  if (!tried.swept) return true;
  if (tried.worse && !current.worse_at[pose][region]) return false;
  return tried.excess <= std::max(current.excess_at[pose][region], kNearlyWorse) + kSameExcess;
}

// Whether `after` (every pair acceptable) may replace `before`: fewer pairs worse, no more edges
// stretched beyond 1.3x.
bool better(const BindingVerdict& before, const BindingVerdict& after) {
  const Score was = score(before), is = score(after);
  return is.pairs < was.pairs && is.stretched <= was.stretched;
}

// Where each of `part`'s vertices is in `whole`'s (both ascending model indices).
std::vector<std::uint32_t> places_in(const std::vector<std::uint32_t>& whole,
                                     const std::vector<std::uint32_t>& part) {
  std::vector<std::uint32_t> places;
  for (const std::uint32_t v : part)
    places.push_back(static_cast<std::uint32_t>(std::lower_bound(whole.begin(), whole.end(), v) -
                                                whole.begin()));
  return places;
}

// The sweep's positions of the measured vertices (the checker's meter's, in its order) and its
// figures, per pose: the body as the adaptation has it so far.
struct BodyState {
  std::vector<std::vector<glm::vec3>> positions;
  SweepFigures figures;
};

// One sweep's candidates judged by what they change: in the regions its vertices touch, the
// edges and triangles with a vertex on the sweep are measured again on those vertices and their
// neighbours posed alone, the others' figures once per pose from the body's positions (when a
// candidate first reaches the pose); the regions it does not touch keep the body's figures.
class SweepTrial {
 public:
  SweepTrial(const deform::BoundModel& bound, int sweep, const BindingChecker& checker,
             const BodyState& body, const BindingVerdict& current)
      : checker_(checker), body_(body) {
    std::vector<std::uint8_t>& moving = on_sweep_flag_;
    moving.assign(bound.vertices.size(), 0);
    for (std::uint32_t v = 0; v < bound.vertices.size(); ++v)
      for (int k = 0; k < deform::kSweepsPerVertex; ++k)
        if (bound.vertices[v].sweep[k] == sweep) {
          moving[v] = 1;
          on_sweep_.push_back(v);
          break;
        }
    const metrics::SweptStretchMeter& whole = checker.meter();
    touched_ = whole.regions_touched(moving);
    beside_.emplace(whole.part(moving, false));
    beside_places_ = places_in(whole.vertices(), beside_->vertices());
    beside_figures_.resize(body.positions.size());
    beside_stretched_.resize(body.positions.size());
    changed_.emplace(whole.part(moving, true));
    changed_places_ = places_in(whole.vertices(), changed_->vertices());
    // The poses by the largest stretch excess of a touched region not yet worse, descending:
    // where a candidate most likely loses a pair, so that a losing one stops early.
    std::vector<float> nearest(current.worse_at.size(), 0.0f);
    for (std::size_t p = 0; p < nearest.size(); ++p) {
      order_.push_back(static_cast<int>(p));
      for (std::size_t r = 0; r < touched_.size(); ++r)
        if (touched_[r] && !current.worse_at[p][r])
          nearest[p] = std::max(nearest[p], current.excess_at[p][r]);
    }
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return nearest[a] > nearest[b]; });
    // The probe's first edges: in every pose, each touched region's longest edge on the sweep
    // as bound, where a candidate most likely stretches past it (14 of the 72k mannequin's 15
    // candidates lose on these or their neighbours).
    probe_seed_.assign(bound.vertices.size(), 0);
    std::vector<std::vector<std::optional<std::array<std::uint32_t, 2>>>> longest(
        body.positions.size());  // per pose and touched region
    deform::run_in_vertex_blocks(
        body.positions.size(), kCheckThreads, [&](std::size_t begin, std::size_t end) {
          std::vector<glm::vec3> at(changed_places_.size());
          for (std::size_t p = begin; p < end; ++p) {
            for (std::size_t k = 0; k < changed_places_.size(); ++k)
              at[k] = body.positions[p][changed_places_[k]];
            for (std::size_t r = 0; r < touched_.size(); ++r)
              if (touched_[r])
                longest[p].push_back(changed_->longest_edge(at, static_cast<int>(r)));
          }
        });
    for (const auto& edges : longest)
      for (const auto& edge : edges) seed(edge);
  }
  // The model vertices the sweep's candidates re-bind.
  const std::vector<std::uint32_t>& on_sweep() const { return on_sweep_; }

  // `bound` (this sweep re-bound) measured: the figures of the whole meter, and the changed
  // vertices' positions; none when a (pose, region) pair is not acceptable against `current`
  // (pair_acceptable: the poses are measured nearest to losing first, and it stops there).
  std::optional<SweepFigures> measure(const deform::BoundModel& bound,
                                      const BindingVerdict& current,
                                      std::vector<std::vector<glm::vec3>>& changed_positions) {
    SweepFigures figures = body_.figures;
    changed_positions.assign(figures.figures.size(), {});
    std::vector<std::uint8_t> refused(figures.figures.size(), 0);  // per pose
    // Per pose: the longest edge of each region that refused there, for the probe.
    std::vector<std::vector<std::array<std::uint32_t, 2>>> refusing(figures.figures.size());
    const bool acceptable = checker_.pose_each(
        bound, changed_->vertices(), order_, [&](int p, std::span<const glm::vec3> at) {
          // Called for two poses at once (pose_each): it writes pose p's entries alone.
          changed_positions[p].assign(at.begin(), at.end());
          bool kept = true;
          std::vector<metrics::RegionFigures> measured;
          std::vector<int> stretched;
          changed_->measure(at, checker_.world(p), measured, stretched);
          measure_beside(p);
          metrics::SweptStretchMeter::combine(measured, stretched, beside_figures_[p],
                                              beside_stretched_[p]);
          for (std::size_t r = 0; r < touched_.size(); ++r) {
            if (!touched_[r]) continue;
            figures.figures[p][r] = measured[r];
            figures.stretched[p][r] = stretched[r];
            const auto region = static_cast<int>(r);
            if (!pair_acceptable(current, p, region, checker_.compare(p, region, measured[r]))) {
              kept = false;
              if (const auto edge = changed_->longest_edge(at, region))
                refusing[p].push_back(*edge);
            }
          }
          refused[p] = !kept;
          return kept;
        });
    if (!acceptable) {
      for (const auto& edges : refusing)
        for (const auto& edge : edges) seed(edge);
      judge_refusing_pose_first(refused);
      return std::nullopt;
    }
    return figures;
  }

  // The model vertices a candidate binds first (its probe's on the sweep; probe_refuses).
  const std::vector<std::uint32_t>& probe_on_sweep() {
    make_probe();
    return probe_on_sweep_;
  }
  // Whether `bound` (this sweep re-bound, probe_on_sweep() at least) loses a pair it may not on
  // the probe's edges and triangles alone (the seeds' and their neighbours'): then measure()
  // refuses it too, as they are some of the items it reads and the figures judged (a region's
  // largest ratio, its flipped count) can only grow with more items. A candidate refused here
  // costs a few hundred vertices bound and posed instead of the sweep's thousands.
  bool probe_refuses(const deform::BoundModel& bound, const BindingVerdict& current) {
    make_probe();
    std::vector<std::uint8_t> refused(order_.size(), 0);  // per pose
    const bool acceptable = checker_.pose_each(
        bound, probe_->vertices(), order_, [&](int p, std::span<const glm::vec3> at) {
          std::vector<metrics::RegionFigures> measured;
          std::vector<int> stretched;
          probe_->measure(at, checker_.world(p), measured, stretched);
          bool kept = true;
          for (std::size_t r = 0; r < touched_.size(); ++r) {
            const auto region = static_cast<int>(r);
            if (touched_[r] &&
                !pair_acceptable(current, p, region, checker_.compare(p, region, measured[r])))
              kept = false;
          }
          refused[p] = !kept;
          return kept;
        });
    if (!acceptable) judge_refusing_pose_first(refused);
    return !acceptable;
  }
  // The figures of the items beside the sweep in pose p, measured on the body's positions when
  // a candidate first reaches that pose: most candidates lose a pair within the first few poses
  // of order_, so the other poses' are never needed (the same figures as measuring every pose
  // up front).
  void measure_beside(int p) const {
    if (!beside_figures_[p].empty()) return;
    std::vector<glm::vec3> positions;
    for (const std::uint32_t i : beside_places_) positions.push_back(body_.positions[p][i]);
    beside_->measure(positions, checker_.world(p), beside_figures_[p], beside_stretched_[p]);
  }
  // The sweep's next candidate is judged on the pose that refused this one first: a sweep's
  // candidates mostly lose the same pair, and the verdict needs every pose acceptable, so the
  // order changes how soon a refusal comes, not what is refused.
  void judge_refusing_pose_first(const std::vector<std::uint8_t>& refused) {
    const auto first_refused =
        std::find_if(order_.begin(), order_.end(), [&](int p) { return refused[p] != 0; });
    if (first_refused != order_.end())
      std::rotate(order_.begin(), first_refused, first_refused + 1);
  }
  void seed(const std::optional<std::array<std::uint32_t, 2>>& edge) {
    if (!edge) return;
    for (const std::uint32_t v : *edge)
      if (!probe_seed_[v]) probe_seed_[v] = 1, probe_.reset();
  }
  // The probe: the changed items with a seed vertex, once per set of seeds.
  void make_probe() {
    if (probe_) return;
    probe_.emplace(changed_->part(probe_seed_, true));
    probe_on_sweep_.clear();
    for (const std::uint32_t v : probe_->vertices())
      if (on_sweep_flag_[v]) probe_on_sweep_.push_back(v);
  }
  // A candidate's measure made the body's.
  void keep(const std::vector<std::vector<glm::vec3>>& changed_positions, SweepFigures figures,
            BodyState& body) const {
    for (std::size_t p = 0; p < body.positions.size(); ++p)
      for (std::size_t i = 0; i < changed_places_.size(); ++i)
        body.positions[p][changed_places_[i]] = changed_positions[p][i];
    body.figures = std::move(figures);
  }

 private:
  const BindingChecker& checker_;
  const BodyState& body_;
  std::vector<std::uint32_t> on_sweep_;
  std::vector<std::uint8_t> on_sweep_flag_;  // per model vertex
  std::vector<std::uint8_t> touched_;        // per region
  // The items in the touched regions without a vertex on the sweep, their vertices' places in
  // the body's positions, and their figures per pose (empty until measure_beside).
  std::optional<metrics::SweptStretchMeter> beside_;
  std::vector<std::uint32_t> beside_places_;
  mutable std::vector<std::vector<metrics::RegionFigures>> beside_figures_;
  mutable std::vector<std::vector<int>> beside_stretched_;
  std::optional<metrics::SweptStretchMeter> changed_;
  std::vector<std::uint32_t> changed_places_;
  // The poses, in the order measured: nearest to losing first, then each refusing pose moved
  // to the front.
  std::vector<int> order_;
  // Per model vertex: an end of an edge that was longest where a candidate may lose (seed);
  // the probe measured on them (rebuilt when a seed is added), and its vertices on the sweep.
  std::vector<std::uint8_t> probe_seed_;
  std::optional<metrics::SweptStretchMeter> probe_;
  std::vector<std::uint32_t> probe_on_sweep_;
};

}  // namespace

int BindingVerdict::worse_pairs() const { return score(*this).pairs; }

Adaptation adapt_binding(deform::BoundModel& bound, const BindingChecker& checker) {
  BodyState body;
  body.positions = checker.sweep_positions(bound, checker.meter().vertices());
  body.figures = checker.measure(checker.meter(), body.positions);
  Adaptation adaptation;
  adaptation.before = checker.judge(body.figures);
  BindingVerdict verdict = adaptation.before;
  std::optional<deform::SweepRebinder> rebinder;
  for (int s = 0; s < static_cast<int>(bound.sweeps.size()); ++s) {
    const deform::BodyPart part = bound.sweeps[s].part;
    if (!sweep_loses(verdict, part)) continue;
    if (!rebinder) rebinder.emplace(bound);
    SweepTrial trial(bound, s, checker, body, verdict);
    const deform::SweepChoice current = bound.sweeps[s].choice;
    const deform::OrientationCurveKind other =
        current.orientation_curve == deform::OrientationCurveKind::kLinear
            ? deform::OrientationCurveKind::kSmooth
            : deform::OrientationCurveKind::kLinear;
    const int other_keys = current.keys_per_link == 1 ? 2 : 1;
    // Only the sweep and its vertices' bindings change: those are kept to restore.
    const deform::BoundSweep kept_sweep = bound.sweeps[s];
    std::vector<deform::VertexBinding> kept_vertices;
    for (const std::uint32_t v : trial.on_sweep()) kept_vertices.push_back(bound.vertices[v]);
    struct Best {
      deform::BoundSweep sweep;
      std::vector<deform::VertexBinding> vertices;
      BindingVerdict verdict;
      SweepFigures figures;
      std::vector<std::vector<glm::vec3>> positions;
    };
    std::optional<Best> best;
    for (const auto& [keys, curve] :
         {std::pair{other_keys, current.orientation_curve}, std::pair{current.keys_per_link, other},
          std::pair{other_keys, other}}) {
      const deform::SweepChoice choice{
          .orientation_curve = curve,
          .keys_per_link = keys,
          .origin = deform::SweepChoiceOrigin::kSelfCheck,
          .worse_before = static_cast<std::uint32_t>(verdict.worse_pairs())};
      std::optional<SweepFigures> figures;
      std::vector<std::vector<glm::vec3>> positions;
      try {
        // Its likeliest losing edges first; bound whole and measured only where they pass.
        rebinder->rebind_vertices(bound, s, choice, trial.probe_on_sweep());
        if (!trial.probe_refuses(bound, verdict)) {
          rebinder->rebind(bound, s, choice);
          figures = trial.measure(bound, verdict, positions);
        }
      } catch (const std::invalid_argument&) {
        continue;  // this choice cannot be fitted: not a candidate
      }
      BindingVerdict tried;
      if (figures) tried = checker.judge(*figures);
      if (figures && better(verdict, tried) && (!best || score(tried) < score(best->verdict))) {
        best =
            Best{bound.sweeps[s], {}, std::move(tried), std::move(*figures), std::move(positions)};
        for (const std::uint32_t v : trial.on_sweep()) best->vertices.push_back(bound.vertices[v]);
      }
      bound.sweeps[s] = kept_sweep;
      for (std::size_t i = 0; i < kept_vertices.size(); ++i)
        bound.vertices[trial.on_sweep()[i]] = kept_vertices[i];
    }
    if (!best) continue;
    bound.sweeps[s] = std::move(best->sweep);
    for (std::size_t i = 0; i < best->vertices.size(); ++i)
      bound.vertices[trial.on_sweep()[i]] = best->vertices[i];
    trial.keep(best->positions, std::move(best->figures), body);
    verdict = std::move(best->verdict);
    bound.sweeps[s].choice.worse_after = static_cast<std::uint32_t>(verdict.worse_pairs());
  }
  adaptation.after = std::move(verdict);
  return adaptation;
}

std::vector<std::string> adaptation_notes(const deform::BoundModel& bound) {
  std::vector<std::string> notes;
  for (const deform::BoundSweep& sweep : bound.sweeps) {
    const deform::SweepChoice& c = sweep.choice;
    if (c.origin != deform::SweepChoiceOrigin::kSelfCheck) continue;
    char text[240];
    std::snprintf(
        text, sizeof text,
        "%s sweep: %d link key%s per link, %s orientation curve (worse than skinning "
        "in %u (pose, region) pairs before, %u after)",
        deform::to_string(sweep.part), c.keys_per_link, c.keys_per_link == 1 ? "" : "s",
        c.orientation_curve == deform::OrientationCurveKind::kSmooth ? "smooth" : "linear",
        c.worse_before, c.worse_after);
    notes.push_back(text);
  }
  return notes;
}

CheckedBinding bind_checked(const deform::Model& model, const deform::RigMap& rig,
                            const deform::BindOptions& options, bool adapt,
                            const deform::BindProgress& progress, bool sweep_carried_ends) {
  const auto started = std::chrono::steady_clock::now();
  CheckedBinding checked;
  checked.bound = deform::bind(model, rig, options, progress, sweep_carried_ends);
  const auto bound_at = std::chrono::steady_clock::now();
  const BindingChecker checker(checked.bound, range_of_motion_peaks(checked.bound));
  if (adapt) {
    Adaptation adaptation = adapt_binding(checked.bound, checker);
    checked.before = std::move(adaptation.before);
    checked.verdict = std::move(adaptation.after);
  } else {
    checked.before = checker.verdict(checked.bound);
    checked.verdict = checked.before;
  }
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
