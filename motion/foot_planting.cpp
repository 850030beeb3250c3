#include "motion/foot_planting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "deform/model/forward_kinematics.h"
#include "motion/contact_timing.h"
#include "motion/two_bone_ik.h"

namespace sweepd::motion {

namespace {

// Fractions of the hip height (see the header): a 0.9 m hip gives 6.3 cm and 0.36 m/s.
constexpr float kSoleContactHeight = 0.07f;
constexpr float kMostFloat = 0.1f;        // a body floating higher has no floor to come down to
constexpr double kStanceQuantile = 0.02;  // of a foot's heights over the clip: where it stands
// A planted leg's reach, short of its length by this fraction at least: its knee bent by about 5°
// (equal bones), where the IK's knee angle is well conditioned (see sole_of).
constexpr float kStraightestPlant = 0.001f;
// m: sole points this close to the lowest share its step (see measure_soles): far above float
// round-off on a metre-sized body, far below a sole that is not flat.
constexpr float kPivotTie = 1e-5f;
// s: the Gaussian weights' deviation of the line fitted to a planted foot's rotations.
constexpr double kSteadyRoll = 0.05;

// The y of `world * local`, summed in glm's order for mat4 * vec4 so that it is bit-identical,
// without the three rows nobody reads: the sole search runs over every sole vertex on every frame
// of a clip (FootPlanting::build) and on every pose served (apply), and under the sanitizers'
// -O1 the whole product was most of a retarget's time.
float height_of(const glm::mat4& world, const glm::vec4& local) {
  return (world[0].y * local.x + world[1].y * local.y) +
         (world[2].y * local.z + world[3].y * local.w);
}

// A rotation as its axis times its angle (rad), well conditioned for small turns (acos of the
// quaternion's w is not: it loses half the float's digits near the identity).
glm::dvec3 turn_vector(glm::quat q) {
  if (q.w < 0.0f) q = -q;
  const glm::dvec3 v(q.x, q.y, q.z);
  const double sine = glm::length(v);
  return sine > 0.0 ? v * (2.0 * std::atan2(sine, double{q.w}) / sine) : glm::dvec3(0.0);
}

}  // namespace

FootPlanting::FootPlanting(const deform::Model& model, float floor, double frame_time)
    : skeleton_(model.skeleton),
      rest_inverse_(deform::world_rest_inverse_matrices(model.skeleton)),
      floor_(floor),
      frame_time_(frame_time) {}

std::optional<FootPlanting> FootPlanting::build(
    const deform::Model& model, const deform::RigMap& map, float hip_height, int frame_count,
    double frame_time, const std::function<deform::Pose(int)>& frame_pose,
    const std::vector<float>& lowered) {
  if (model.positions.empty() || frame_count < 1 || !(frame_time > 0.0) || !(hip_height > 0.0f))
    return std::nullopt;
  if (!lowered.empty() && static_cast<int>(lowered.size()) != frame_count)
    throw std::invalid_argument("foot planting: a drop per clip frame is needed");
  float floor = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : model.positions) floor = std::min(floor, p.y);
  FootPlanting planting(model, floor, frame_time);
  planting.frame_count_ = frame_count;
  planting.lowered_ = lowered;
  const std::vector<glm::mat4> rest = model.skeleton.world_rest_matrices();
  for (int side = 0; side < 2; ++side) {
    const deform::LegJoints& leg = side == 0 ? map.left_leg : map.right_leg;
    if (leg.upper < 0 || leg.lower < 0 || leg.foot < 0) continue;
    Foot foot{leg, {}, glm::vec4(0.0f), {}, {}, {}, {}, side};
    glm::vec3 centre(0.0f);
    const float ankle_height = rest[leg.foot][3].y;
    for (std::size_t v = 0; v < model.positions.size(); ++v) {
      const int joint = model.strongest_joint(v);
      if (model.positions[v].y > ankle_height || !is_at_or_below(model.skeleton, joint, leg.foot))
        continue;
      foot.sole.push_back(
          {joint, planting.rest_inverse_[joint] * glm::vec4(model.positions[v], 1.0f)});
      centre += model.positions[v];
    }
    if (foot.sole.empty()) continue;
    centre /= static_cast<float>(foot.sole.size());
    foot.centre = planting.rest_inverse_[leg.foot] * glm::vec4(centre, 1.0f);
    planting.feet_.push_back(std::move(foot));
  }
  if (planting.feet_.empty()) return std::nullopt;

  // The soles as the clip moves the feet, and contacts from them; then the planted feet's roll
  // steadied (see the header) and everything found again on the steadied feet, the contacts
  // found first kept (a foot is steadied only on and around them).
  std::vector<std::vector<glm::quat>> foot_rotation;
  planting.plan(planting.measure_soles(frame_pose, &foot_rotation), hip_height);
  if (!planting.steady_feet(foot_rotation)) return planting;
  planting.plan(planting.measure_soles(
                    [&](int f) {
                      deform::Pose pose = frame_pose(f);
                      planting.steady(f, f, 0.0f, pose);
                      return pose;
                    },
                    nullptr),
                hip_height, true);
  return planting;
}

std::vector<std::vector<FootPlanting::Sole>> FootPlanting::measure_soles(
    const std::function<deform::Pose(int)>& frame_pose,
    std::vector<std::vector<glm::quat>>* foot_rotation) const {
  const int frame_count = frame_count_;
  const double frame_time = frame_time_;
  // Each frame's soles, with the speed of each one's lowest point: that point of the foot,
  // kSpeedWindow before and after (not the lowest point of those frames, which jumps between
  // heel and toes while the foot rolls, and can stand still under a foot that swings), in
  // three dimensions (a foot coming down to land is not planted yet), over a window wide
  // enough that marker noise (a landing foot jittering 2-3 cm between 120 Hz frames in
  // cmu_01_03) does not decide it.
  const int reach = std::max(1, static_cast<int>(std::lround(kSpeedWindow / frame_time)));
  const int ring = 2 * reach + 1;
  std::vector<std::vector<glm::mat4>> world(ring, std::vector<glm::mat4>(skeleton_.joints.size()));
  const auto posed = [&](int f) -> const std::vector<glm::mat4>& { return world[f % ring]; };
  if (foot_rotation) foot_rotation->assign(feet_.size(), std::vector<glm::quat>(frame_count));
  const auto pose_frame = [&](int f) {
    const deform::Pose pose = frame_pose(f);
    deform::forward_kinematics(skeleton_, pose, world[f % ring]);
    if (!foot_rotation) return;
    const std::vector<glm::quat> rotation = world_rotations(skeleton_, pose);
    for (std::size_t i = 0; i < feet_.size(); ++i)
      (*foot_rotation)[i][f] = rotation[feet_[i].leg.foot];
  };
  for (int f = 0; f < std::min(reach, frame_count); ++f) pose_frame(f);
  std::vector<std::vector<Sole>> soles(feet_.size());
  for (int f = 0; f < frame_count; ++f) {
    if (f + reach < frame_count) pose_frame(f + reach);
    const int a = std::max(f - reach, 0), b = std::min(f + reach, frame_count - 1);
    for (std::size_t i = 0; i < feet_.size(); ++i) {
      const Foot& foot = feet_[i];
      Sole sole = sole_of(foot, posed(f));
      const SolePoint& point = foot.sole[sole.lowest];
      const glm::vec3 moved(posed(b)[point.joint] * point.local -
                            posed(a)[point.joint] * point.local);
      sole.speed = b > a ? glm::length(moved) / static_cast<float>((b - a) * frame_time) : 0.0f;
      if (f + 1 < frame_count) {
        // The step of the points within kPivotTie of the lowest, weighted down to nothing at
        // kPivotTie above it: a flat foot's heel and toes tie for lowest, and round-off chose
        // between points 4.5e-8 m apart whose steps differed by 3.9e-5 m (the male in cmu_01_03
        // frame 1660, the clip read in metres against centimetres), which moved the held foot.
        const float low = sole.height + floor_;
        glm::vec3 step(0.0f);
        float weights = 0.0f;
        for (const SolePoint& tied : foot.sole) {
          const float w = 1.0f - (height_of(posed(f)[tied.joint], tied.local) - low) / kPivotTie;
          if (w <= 0.0f) continue;
          step += w * glm::vec3(posed(f + 1)[tied.joint] * tied.local -
                                posed(f)[tied.joint] * tied.local);
          weights += w;
        }
        step /= weights;
        sole.step = glm::vec2(step.x, step.z);
      }
      soles[i].push_back(sole);
    }
  }
  return soles;
}

FootPlanting::Sole FootPlanting::sole_of(const Foot& foot,
                                         const std::vector<glm::mat4>& world) const {
  Sole lowest{
      std::numeric_limits<float>::infinity(), 0, 0.0f, glm::vec2(0.0f), glm::vec3(0.0f), 0.0f};
  for (std::size_t k = 0; k < foot.sole.size(); ++k) {
    const float y = height_of(world[foot.sole[k].joint], foot.sole[k].local);
    if (y < lowest.height) lowest.height = y, lowest.lowest = k;
  }
  lowest.height -= floor_;
  const glm::vec3 hip(world[foot.leg.upper][3]), knee(world[foot.leg.lower][3]),
      ankle(world[foot.leg.foot][3]);
  lowest.to_ankle = ankle - hip;
  // A planted leg straightens no further than the clip's own, or than kSoftReach short of its
  // length where the clip's is bent more: a nearly straight knee under a held ankle moves
  // several times as far as the hip (a model straightening a knee the clip bends 23° to 0.2°
  // stepped it 5 cm in a frame, the male in cmu_01_01 frame 980).
  // Never quite straight, though (kStraightestPlant): at a straight knee the IK's bend angle is
  // the arc cosine of a number at 1, where float round-off moves the knee by up to 0.07 mm (the
  // same clip read in metres and in centimetres, cmu_01_03 frame 2476).
  const float length = glm::distance(hip, knee) + glm::distance(knee, ankle);
  lowest.leg = std::clamp(glm::length(lowest.to_ankle), (1.0f - kSoftReach) * length,
                          (1.0f - kStraightestPlant) * length);
  return lowest;
}

float FootPlanting::hip_drop(const Sole& sole, glm::vec2 shift) {
  const glm::vec3 to_target = sole.to_ankle + glm::vec3(shift.x, -sole.height, shift.y);
  const float across = glm::length(glm::vec2(to_target.x, to_target.z));
  return std::max(0.0f,
                  -to_target.y - std::sqrt(std::max(0.0f, sole.leg * sole.leg - across * across)));
}

void FootPlanting::spread(std::vector<glm::vec3>& values,
                          const std::vector<std::uint8_t>& known) const {
  const int n = static_cast<int>(values.size());
  std::vector<int> previous(n, -1), next(n, -1);
  for (int f = 0, last = -1; f < n; ++f) previous[f] = last = known[f] ? f : last;
  for (int f = n - 1, last = -1; f >= 0; --f) next[f] = last = known[f] ? f : last;
  for (int f = 0; f < n; ++f) {
    if (known[f]) continue;
    const int p = previous[f], q = next[f];
    if (p >= 0 && q >= 0 && (q - p) * frame_time_ < 2.0 * kFade) {
      values[f] =
          glm::mix(values[p], values[q], static_cast<float>(f - p) / static_cast<float>(q - p));
      continue;
    }
    const auto fade = [&](int contact) {
      if (contact < 0) return glm::vec3(0.0f);
      const double seconds = std::abs(f - contact) * frame_time_;
      return values[contact] * static_cast<float>(std::max(0.0, 1.0 - seconds / kFade));
    };
    values[f] = fade(p) + fade(q);
  }
}

float FootPlanting::stance(const std::vector<Sole>& soles) {
  std::vector<float> heights;
  for (const Sole& sole : soles) heights.push_back(sole.height);
  const std::size_t at = static_cast<std::size_t>(kStanceQuantile * (heights.size() - 1));
  std::nth_element(heights.begin(), heights.begin() + at, heights.end());
  return heights[at];
}

void FootPlanting::plan(const std::vector<std::vector<Sole>>& soles, float hip_height,
                        bool keep_contacts) {
  const int n = frame_count_;
  // A body the retargeting floats (its proportions are not the clip's) comes down on every
  // frame by the lower foot's stance; one that floats higher than kMostFloat never stands.
  float lower = std::numeric_limits<float>::infinity();
  for (const std::vector<Sole>& sole : soles) lower = std::min(lower, stance(sole));
  const float settle = lower > 0.0f && lower <= kMostFloat * hip_height ? lower : 0.0f;
  // Contacts, their feet's shifts across (pin), then how far the hip comes down on each frame:
  // settle, or more where a leg too short to reach its shifted ankle needs it, eased in and out (a
  // foot's need at frame f asks for need * (1 - |t - t_f| / kFade) around it, so the body never
  // drops faster than the largest need per kFade). Dropping the body can bring a slow foot into
  // contact, so contacts are found again until none is added (twice at most in practice).
  hip_drop_.assign(n, settle);
  const int fade_frames = static_cast<int>(kFade / frame_time_);
  // Each frame's need spreads kFade either side, falling linearly (the drop is their envelope).
  const auto ease_in = [&](int f, float drop) {
    for (int g = std::max(0, f - fade_frames); g <= std::min(n - 1, f + fade_frames); ++g) {
      const float ease = 1.0f - static_cast<float>(std::abs(g - f)) / (fade_frames + 1);
      hip_drop_[g] = std::max(hip_drop_[g], settle + (drop - settle) * ease);
    }
  };
  for (int f = 0; f < static_cast<int>(lowered_.size()); ++f)
    if (lowered_[f] > settle) ease_in(f, lowered_[f]);
  const auto is_down = [&](std::size_t i, int f) {
    return soles[i][f].height - hip_drop_[f] <= kSoleContactHeight * hip_height;
  };
  for (Foot& foot : feet_) {
    if (!keep_contacts) foot.contact.assign(n, 0);
    foot.offset.assign(n, glm::vec3(0.0f));
  }
  for (int round = 0; round < 4; ++round) {
    bool added = false;
    for (std::size_t i = 0; i < feet_.size(); ++i) {
      const auto down = [&](int f) { return is_down(i, f); };
      std::vector<std::uint8_t>& contact = feet_[i].contact;
      for (int f = 0; f < n; ++f)
        if (!contact[f] && down(f) && soles[i][f].speed < kContactSpeed * hip_height) {
          contact[f] = 1;
          added = true;
        }
      // A contact broken for no longer than the speed window, the sole down throughout, goes
      // on: one noisy frame makes the window fast for that long (held apart, the two contacts'
      // shifts would jump).
      for (int f = 0, last = -1; f < n; ++f) {
        if (!contact[f]) continue;
        bool bridged =
            last >= 0 && f - last > 1 && (f - last - 1) * frame_time_ <= 2.0 * kSpeedWindow;
        for (int g = last + 1; bridged && g < f; ++g) bridged = down(g);
        if (bridged) {
          std::fill(contact.begin() + last + 1, contact.begin() + f, 1);
          added = true;
        }
        last = f;
      }
    }
    if (!added && !(keep_contacts && round == 0)) break;
    std::vector<float> need(n, 0.0f);
    for (std::size_t i = 0; i < feet_.size(); ++i) {
      pin(feet_[i], soles[i]);
      for (int f = 0; f < n; ++f)
        if (feet_[i].contact[f]) {
          const glm::vec3 shift = feet_[i].offset[f];
          need[f] = std::max(need[f], hip_drop(soles[i][f], {shift.x, shift.z}) - settle);
        }
    }
    for (int f = 0; f < n; ++f)
      if (need[f] > 0.0f) ease_in(f, settle + need[f]);
  }
  for (std::size_t i = 0; i < feet_.size(); ++i) {
    Foot& foot = feet_[i];
    for (int f = 0; f < n; ++f)
      if (foot.contact[f]) foot.offset[f].y = hip_drop_[f] - soles[i][f].height;
    // Across, a contact's shift holds while the sole stays down after it and before it, and
    // fades beyond: fading at once slowed a foot peeling off to a hover above the floor (the
    // child's in cmu_01_03, 2.3 cm up and slower than a viewer's 0.19 m/s). A gap down
    // throughout is bridged, and so is one where the two holds would leave less than kFade
    // between them (the heavy male's right foot in cmu_01_01, down all but frame 1165 of a
    // 0.3 s gap, had its shift jump 4.4 cm across in two frames).
    std::vector<glm::vec3> across = foot.offset;
    std::vector<std::uint8_t> held = foot.contact;
    for (int f = 0; f < n;) {
      if (foot.contact[f]) {
        ++f;
        continue;
      }
      int end = f;
      while (end < n && !foot.contact[end]) ++end;
      int a = f, b = end;
      for (; f > 0 && a < end && is_down(i, a); ++a) across[a] = across[f - 1], held[a] = 1;
      for (; end < n && b > a && is_down(i, b - 1); --b)
        across[b - 1] = across[end], held[b - 1] = 1;
      if (f > 0 && end < n && (b - a) * frame_time_ < kFade)
        std::fill(held.begin() + f, held.begin() + end, 0);
      f = end;
    }
    spread(across, held);
    spread(foot.offset, foot.contact);
    for (int f = 0; f < n; ++f) foot.offset[f].x = across[f].x, foot.offset[f].z = across[f].z;
    soften(foot);
  }
}

void FootPlanting::soften(Foot& foot) const {
  const int n = frame_count_;
  const int ramp = std::max(1, static_cast<int>(std::lround(kFade / frame_time_)));
  std::vector<int> distance(n, ramp);
  for (int f = 0, last = -ramp; f < n; ++f) {
    if (foot.contact[f]) last = f;
    distance[f] = std::min(ramp, f - last);
  }
  for (int f = n - 1, next = n - 1 + ramp; f >= 0; --f) {
    if (foot.contact[f]) next = f;
    distance[f] = std::min(distance[f], next - f);
  }
  foot.softness.resize(n);
  for (int f = 0; f < n; ++f)
    foot.softness[f] = kSoftReach * static_cast<float>(distance[f]) / static_cast<float>(ramp);
}

void FootPlanting::pin(Foot& foot, const std::vector<Sole>& soles) const {
  const int n = frame_count_;
  for (int first = 0; first < n;) {
    if (!foot.contact[first]) {
      ++first;
      continue;
    }
    // Each frame's shift holds the point lowest at the frame before where it was then; the
    // contact's mean shift is then taken off, so the ankle stands where the clip's does on
    // average (footfalls and strides keep their places).
    int last = first;
    glm::vec2 shift(0.0f), sum(0.0f);
    foot.offset[first] = glm::vec3(0.0f);
    while (last + 1 < n && foot.contact[last + 1]) {
      shift -= soles[last].step;
      sum += shift;
      ++last;
      foot.offset[last] = glm::vec3(shift.x, 0.0f, shift.y);
    }
    const glm::vec3 mean(sum.x / (last - first + 1), 0.0f, sum.y / (last - first + 1));
    for (int f = first; f <= last; ++f) foot.offset[f] -= mean;
    first = last + 1;
  }
}

bool FootPlanting::steady_feet(const std::vector<std::vector<glm::quat>>& foot_rotation) {
  const int n = frame_count_;
  const double sigma = kSteadyRoll / frame_time_;  // frames
  const int half = static_cast<int>(std::ceil(3.0 * sigma));
  bool any = false;
  for (std::size_t i = 0; i < feet_.size(); ++i) {
    Foot& foot = feet_[i];
    const std::vector<glm::quat>& rotation = foot_rotation[i];
    foot.steadying.assign(n, glm::vec3(0.0f));
    // Each contact frame's rotation: the contact's rotations about it, Gaussian-weighted, on
    // its own frames only (the foot landing or peeling off is not averaged in).
    for (int first = 0; first < n;) {
      if (!foot.contact[first]) {
        ++first;
        continue;
      }
      int last = first;
      while (last + 1 < n && foot.contact[last + 1]) ++last;
      for (int f = first; f <= last; ++f) {
        // A line fitted to the rotations about f (as turns from f's own, weighted least
        // squares): its value at f. A plain mean lags where the foot keeps rolling one way (heel
        // lifting at the contact's end); the line follows the roll and drops the jitter.
        double weights = 0.0, moment = 0.0, spread_sq = 0.0;
        glm::dvec3 sum(0.0), sum_moment(0.0);
        for (int g = std::max(first, f - half); g <= std::min(last, f + half); ++g) {
          const double x = g - f, w = std::exp(-0.5 * x * x / (sigma * sigma));
          const glm::dvec3 v = turn_vector(rotation[g] * glm::inverse(rotation[f]));
          weights += w, moment += w * x, spread_sq += w * x * x;
          sum += w * v, sum_moment += w * x * v;
        }
        const double det = weights * spread_sq - moment * moment;
        const glm::dvec3 at_f =
            det > 1e-9 ? (spread_sq * sum - moment * sum_moment) / det : sum / weights;
        if (glm::length(at_f) > 1e-6) foot.steadying[f] = glm::vec3(at_f), any = true;
      }
      first = last + 1;
    }
    spread(foot.steadying, foot.contact);
  }
  return any;
}

void FootPlanting::steady(int f0, int f1, float alpha, deform::Pose& pose) const {
  const std::vector<glm::quat> rotation = world_rotations(skeleton_, pose);
  for (const Foot& foot : feet_) {
    const glm::vec3 turn = glm::mix(foot.steadying[f0], foot.steadying[f1], alpha);
    const float angle = glm::length(turn);
    if (angle <= 0.0f) continue;
    const int j = foot.leg.foot, parent = skeleton_.joints[j].parent;
    const glm::quat above = parent < 0 ? glm::identity<glm::quat>() : rotation[parent];
    pose.local_rotations[j] =
        glm::normalize(glm::inverse(above) * glm::angleAxis(angle, turn / angle) * rotation[j]);
  }
}

void FootPlanting::apply(double seconds, deform::Pose& pose) const {
  const double position =
      std::clamp(seconds / frame_time_, 0.0, static_cast<double>(frame_count_ - 1));
  const int f0 = static_cast<int>(std::floor(position));
  const int f1 = std::min(f0 + 1, frame_count_ - 1);
  const float alpha = static_cast<float>(position - f0);
  // The pelvis first: every joint comes down with it.
  const float drop = glm::mix(hip_drop_[f0], hip_drop_[f1], alpha);
  pose.root_translation.y -= drop;
  steady(f0, f1, alpha, pose);
  std::vector<glm::mat4> world(skeleton_.joints.size());
  deform::forward_kinematics(skeleton_, pose, world);
  const std::vector<glm::quat> rotation = world_rotations(skeleton_, pose);
  for (const Foot& foot : feet_) {
    const float height = sole_of(foot, world).height;
    glm::vec3 shift = glm::mix(foot.offset[f0], foot.offset[f1], alpha);
    if (foot.contact[f0] && foot.contact[f1]) shift.y = -height;
    shift.y = std::max(shift.y, -height);  // never below the floor
    const float softness = glm::mix(foot.softness[f0], foot.softness[f1], alpha);
    if (shift != glm::vec3(0.0f)) move_ankle(foot, shift, softness, world, rotation, pose);
  }
}

bool FootPlanting::planted(int side, int frame) const {
  for (const Foot& foot : feet_)
    if (foot.side == side) return foot.contact.at(frame) != 0;
  return false;
}

std::vector<FootPlanting::ContactSlide> FootPlanting::contact_slides(
    const std::function<deform::Pose(int)>& frame_pose) const {
  std::vector<ContactSlide> slides;
  std::vector<std::optional<ContactSlide>> open(feet_.size());
  std::vector<glm::mat4> world(skeleton_.joints.size()), next(skeleton_.joints.size());
  if (frame_count_ > 0) deform::forward_kinematics(skeleton_, frame_pose(0), world);
  for (int f = 0; f < frame_count_; ++f) {
    const bool has_next = f + 1 < frame_count_;
    if (has_next) deform::forward_kinematics(skeleton_, frame_pose(f + 1), next);
    for (std::size_t i = 0; i < feet_.size(); ++i) {
      const Foot& foot = feet_[i];
      if (!foot.contact[f]) continue;
      if (!open[i]) open[i] = ContactSlide{foot.side, f, f, 0.0f};
      open[i]->last = f;
      if (has_next && foot.contact[f + 1]) {
        const SolePoint& point = foot.sole[sole_of(foot, world).lowest];
        const glm::vec3 from = world[point.joint] * point.local;
        const glm::vec3 to = next[point.joint] * point.local;
        open[i]->slide += glm::length(glm::vec2(to.x - from.x, to.z - from.z));
      } else {
        slides.push_back(*open[i]);
        open[i].reset();
      }
    }
    std::swap(world, next);
  }
  return slides;
}

void FootPlanting::move_ankle(const Foot& foot, glm::vec3 shift, float softness,
                              const std::vector<glm::mat4>& world,
                              const std::vector<glm::quat>& rotation, deform::Pose& pose) const {
  // A straight leg: the knee bends forward, so the shin turns away from the toes (the sole's
  // centre lies ahead of the ankle).
  const glm::vec3 toes =
      glm::vec3(world[foot.leg.foot] * foot.centre) - glm::vec3(world[foot.leg.foot][3]);
  move_limb_end(skeleton_, {foot.leg.upper, foot.leg.lower, foot.leg.foot}, shift, world, rotation,
                toes, softness, pose);
}

}  // namespace sweepd::motion
