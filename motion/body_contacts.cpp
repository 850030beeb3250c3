#include "motion/body_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "deform/model/forward_kinematics.h"
#include "motion/contact_timing.h"

namespace sweepd::motion {

namespace {

// Fractions of the hip height per second (see the header): 0.23 m/s and 0.72 m/s on a 0.9 m hip.
constexpr float kReturnSpeed = 0.25f;  // per second: a hold fades no faster
constexpr float kFastestHold = 0.8f;   // per second: twice a contact's speed

// Skinning matrices of clip frames, computed when first asked for; frames before `keep_from`
// are dropped.
class FrameSkins {
 public:
  FrameSkins(const deform::Skeleton& skeleton, const std::vector<glm::mat4>& rest_inverse,
             const std::function<deform::Pose(int)>& frame_pose)
      : skeleton_(skeleton),
        rest_inverse_(rest_inverse),
        frame_pose_(frame_pose),
        world_(skeleton.joints.size()) {}
  const std::vector<glm::mat4>& operator()(int frame) {
    auto it = skins_.find(frame);
    if (it != skins_.end()) return it->second;
    deform::forward_kinematics(skeleton_, frame_pose_(frame), world_);
    std::vector<glm::mat4> skin(world_.size());
    deform::skinning_matrices(world_, rest_inverse_, skin);
    return skins_.emplace(frame, std::move(skin)).first->second;
  }
  void keep_from(int frame) {
    while (!skins_.empty() && skins_.begin()->first < frame) skins_.erase(skins_.begin());
  }

 private:
  const deform::Skeleton& skeleton_;
  const std::vector<glm::mat4>& rest_inverse_;
  const std::function<deform::Pose(int)>& frame_pose_;
  std::vector<glm::mat4> world_;
  std::map<int, std::vector<glm::mat4>> skins_;
};

}  // namespace

const char* BodyContacts::name(int part) {
  static constexpr const char* kNames[kPartCount] = {"back",       "hips",      "left knee",
                                                     "right knee", "left hand", "right hand",
                                                     "left arm",   "right arm"};
  return part >= 0 && part < kPartCount ? kNames[part] : "?";
}

std::vector<int> BodyContacts::part_of_joints(const deform::RigMap& map,
                                              const deform::Skeleton& skeleton) {
  const std::vector<deform::BodyPart> body = deform::label_joints(map, skeleton);
  std::vector<int> part(skeleton.joints.size(), -1);
  const auto leg_part = [&](int joint, const deform::LegJoints& leg, Part knee) {
    return leg.lower >= 0 && is_at_or_below(skeleton, joint, leg.lower) ? knee : kHips;
  };
  for (int j = 0; j < skeleton.size(); ++j) {
    switch (body[j]) {
      case deform::BodyPart::kTorso:
        part[j] = j == map.torso.pelvis() ? kHips : kBack;
        break;
      case deform::BodyPart::kNeck:
      case deform::BodyPart::kHead:
        part[j] = kBack;
        break;
      case deform::BodyPart::kLeftArm:
        part[j] = kLeftArm;
        break;
      case deform::BodyPart::kRightArm:
        part[j] = kRightArm;
        break;
      case deform::BodyPart::kLeftHand:
        part[j] = kLeftHand;
        break;
      case deform::BodyPart::kRightHand:
        part[j] = kRightHand;
        break;
      case deform::BodyPart::kLeftLeg:
        part[j] = leg_part(j, map.left_leg, kLeftKnee);
        break;
      case deform::BodyPart::kRightLeg:
        part[j] = leg_part(j, map.right_leg, kRightKnee);
        break;
      default:
        break;
    }
  }
  return part;
}

std::vector<int> BodyContacts::part_of_samples(const deform::RigMap& map,
                                               const deform::Skeleton& skeleton,
                                               const BodySamples& samples) {
  const std::vector<int> part_of = part_of_joints(map, skeleton);
  // A knee's samples lie above its ankle at rest: a shin joint that carries the foot's skin
  // (OpenPose's ankle is a leaf) must not make the sole a knee. Nor is the skin around the
  // ankle that the foot also moves (its blend with the shin: the back of the ankle, beside a
  // planted sole) a knee's: it moves as the foot rolls, and the foot is foot planting's.
  const std::vector<glm::mat4> rest = skeleton.world_rest_matrices();
  const auto foot_of = [&](int part) {
    return part == kLeftKnee ? map.left_leg.foot : map.right_leg.foot;
  };
  const auto moved_by_foot = [&](std::size_t i, int foot) {
    for (int k = 0; k < deform::kInfluences; ++k)
      if (samples.skin_weights(i)[k] > 0.0f &&
          is_at_or_below(skeleton, samples.skin_joints(i)[k], foot))
        return true;
    return false;
  };
  std::vector<int> parts(samples.size(), -1);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int p = part_of[samples.joint(i)];
    if (p == kLeftKnee || p == kRightKnee) {
      const int foot = foot_of(p);
      if (foot >= 0 && (samples.rest(i).y <= rest[foot][3].y || moved_by_foot(i, foot))) continue;
    }
    parts[i] = p;
  }
  return parts;
}

BodyContacts::BodyContacts(const deform::Skeleton& skeleton, double frame_time, int frame_count)
    : skeleton_(skeleton),
      rest_inverse_(deform::world_rest_inverse_matrices(skeleton)),
      frame_time_(frame_time),
      frame_count_(frame_count) {}

BodyContacts BodyContacts::find(const deform::Skeleton& skeleton, const deform::RigMap& map,
                                float hip_height, const BodyFloor& body_floor, int frame_count,
                                double frame_time,
                                const std::function<deform::Pose(int)>& frame_pose,
                                const std::function<bool(int, int)>& foot_planted,
                                const std::function<deform::Pose(int)>& clip_legs_pose) {
  BodyContacts contacts(skeleton, frame_time, frame_count);
  contacts.samples_ = body_floor.samples();
  if (!contacts.samples_) return contacts;
  contacts.hip_height_ = hip_height;
  const deform::ArmJoints* arms[2] = {&map.left_arm, &map.right_arm};
  const deform::LegJoints* legs[2] = {&map.left_leg, &map.right_leg};
  for (int side = 0; side < 2; ++side) {
    contacts.arms_[side] = {arms[side]->upper, arms[side]->lower, arms[side]->hand};
    contacts.legs_[side] = {legs[side]->upper, legs[side]->lower, legs[side]->foot};
  }
  const std::vector<int> part_of = part_of_samples(map, skeleton, *contacts.samples_);
  for (std::size_t i = 0; i < part_of.size(); ++i)
    if (part_of[i] >= 0) contacts.parts_[part_of[i]].samples.push_back(static_cast<int>(i));
  for (PartTrack& track : contacts.parts_) track.contact.assign(frame_count, 0);
  const int parts = std::min(kPartCount, body_floor.group_count());
  if (parts == 0 || frame_count < 1) return contacts;

  const float height = kPartContactHeight * hip_height, speed = kContactSpeed * hip_height;
  const int reach = std::max(1, static_cast<int>(std::lround(kSpeedWindow / frame_time)));
  FrameSkins skin(contacts.skeleton_, contacts.rest_inverse_, frame_pose);
  const BodySamples& samples = *contacts.samples_;
  for (int f = 0; f < frame_count; ++f) {
    skin.keep_from(f - reach);
    const int a = std::max(f - reach, 0), b = std::min(f + reach, frame_count - 1);
    for (int p = 0; p < parts; ++p) {
      const BodyFloor::Lowest low = body_floor.lowest(p, f);
      if (low.sample < 0 || low.height > height || b == a) continue;
      const glm::vec3 moved =
          samples.position(low.sample, skin(b)) - samples.position(low.sample, skin(a));
      if (glm::length(moved) < speed * static_cast<float>((b - a) * frame_time))
        contacts.parts_[p].contact[f] = 1;
    }
  }
  // A contact broken for no longer than the speed window, the part down throughout, goes on.
  for (int p = 0; p < parts; ++p) {
    std::vector<std::uint8_t>& contact = contacts.parts_[p].contact;
    for (int f = 0, last = -1; f < frame_count; ++f) {
      if (!contact[f]) continue;
      bool bridged = last >= 0 && f - last > 1 && (f - last - 1) * frame_time <= 2.0 * kSpeedWindow;
      for (int g = last + 1; bridged && g < f; ++g)
        bridged = body_floor.lowest(p, g).height <= height;
      if (bridged) std::fill(contact.begin() + last + 1, contact.begin() + f, 1);
      last = f;
    }
  }

  // A knee resting beside its planted foot (or within kFade of its planting) is the root's:
  // its leg is foot planting's, so only the hip can hold it.
  for (int side = 0; side < 2; ++side) {
    std::vector<std::uint8_t>& bound = contacts.knee_bound_[side];
    bound.assign(frame_count, 0);
    if (!foot_planted) continue;
    const std::vector<int> distance = contacts.planted_distance(side, foot_planted);
    const std::vector<std::uint8_t>& knee = contacts.parts_[kLeftKnee + side].contact;
    for (int f = 0; f < frame_count; ++f) bound[f] = knee[f] && distance[f] < contacts.taper();
  }
  // The root hold: each frame's step takes off the mean step of the back's and hips' contact
  // points; where neither rests, of the knees' bound to their planted feet; where none of
  // these rests, of the limbs' (knees, hands, arms) where two or more rest.
  contacts.root_held_.assign(frame_count, 0);
  for (int f = 0; f < frame_count; ++f) {
    int torso = 0, limbs = 0;
    for (int p = 0; p < kPartCount; ++p)
      if (contacts.parts_[p].contact[f]) ++(p == kBack || p == kHips ? torso : limbs);
    contacts.root_held_[f] = torso > 0 || limbs > 1 || contacts.knee_bound(f);
    contacts.holds_root_ = contacts.holds_root_ || contacts.root_held_[f];
  }
  contacts.root_shift_.assign(frame_count, glm::vec2(0.0f));
  contacts.refine_root(frame_pose, clip_legs_pose ? clip_legs_pose : frame_pose);
  return contacts;
}

void BodyContacts::refine_root(const std::function<deform::Pose(int)>& frame_pose,
                               const std::function<deform::Pose(int)>& clip_legs_pose) {
  if (!holds_root_) return;
  std::array<bool, kPartCount> every;
  every.fill(true);
  const auto steps = contact_steps(frame_pose, every);
  std::vector<glm::vec2> step(frame_count_, glm::vec2(0.0f));
  // A knee bound to its planted foot is held by its joint on the clip's own legs: there the
  // clip sets the hip's place relative to the knee, and a root shift moves the knee as much
  // as the hip. On the planted legs the IK takes up most of a root shift (the ankle stands),
  // and holding the knee there let the hip sway about it as the clip's root swayed: the
  // thigh turned about the knee, and the kneecap's skin, which the thigh also moves, slid
  // with it (the heavy female's 2.7 cm on the kneeling test clip; her contact point, held
  // instead, slid more with every pass).
  const std::vector<std::array<std::optional<glm::vec2>, 2>> knee_steps =
      knee_joint_steps(clip_legs_pose);
  for (int f = 0; f < frame_count_; ++f) {
    const bool torso = parts_[kBack].contact[f] || parts_[kHips].contact[f];
    const bool knees = knee_bound(f);
    int count = 0;
    for (int side = 0; side < 2 && knees; ++side)
      if (knee_bound_[side][f] && knee_steps[f][side]) step[f] -= *knee_steps[f][side], ++count;
    for (int p = 0; p < kPartCount; ++p) {
      const bool torso_part = p == kBack || p == kHips;
      if (knees || (torso ? !torso_part : torso_part)) continue;
      if (steps[f][p]) step[f] -= *steps[f][p], ++count;
    }
    if (count > 0) step[f] /= static_cast<float>(count);
  }
  // The holds are linear in the steps: what is left on these poses adds to the hold they had.
  const std::vector<glm::vec2> more = hold(root_held_, step);
  for (int f = 0; f < frame_count_; ++f) root_shift_[f] += more[f];
  limit_rate(root_shift_);
}

void BodyContacts::limit_rate(std::vector<glm::vec2>& values) const {
  const float most = kFastestHold * hip_height_ * static_cast<float>(frame_time_);
  for (std::size_t f = 1; f < values.size(); ++f) {
    const glm::vec2 step = values[f] - values[f - 1];
    if (const float length = glm::length(step); length > most)
      values[f] = values[f - 1] + step * (most / length);
  }
}

std::vector<std::array<std::optional<glm::vec2>, BodyContacts::kPartCount>>
BodyContacts::contact_steps(const std::function<deform::Pose(int)>& frame_pose,
                            std::array<bool, kPartCount> which) const {
  std::vector<std::array<std::optional<glm::vec2>, kPartCount>> steps(frame_count_);
  if (!samples_) return steps;
  FrameSkins skin(skeleton_, rest_inverse_, frame_pose);
  for (int f = 0; f + 1 < frame_count_; ++f) {
    skin.keep_from(f);
    for (int p = 0; p < kPartCount; ++p) {
      const PartTrack& track = parts_[p];
      if (!which[p] || !track.contact[f] || !track.contact[f + 1] || track.samples.empty())
        continue;
      // The point of the part lowest on this frame, and where it is on the next.
      int lowest = track.samples.front();
      float y = std::numeric_limits<float>::infinity();
      for (int i : track.samples)
        if (const float h = samples_->height(i, skin(f)); h < y) y = h, lowest = i;
      const glm::vec3 moved =
          samples_->position(lowest, skin(f + 1)) - samples_->position(lowest, skin(f));
      steps[f][p] = glm::vec2(moved.x, moved.z);
    }
  }
  return steps;
}

std::vector<std::array<std::optional<glm::vec2>, 2>> BodyContacts::knee_joint_steps(
    const std::function<deform::Pose(int)>& clip_legs_pose) const {
  std::vector<std::array<std::optional<glm::vec2>, 2>> steps(frame_count_);
  FrameSkins skin(skeleton_, rest_inverse_, clip_legs_pose);
  for (int f = 0; f + 1 < frame_count_; ++f) {
    skin.keep_from(f);
    for (int side = 0; side < 2; ++side) {
      const int knee = legs_[side].lower;
      if (knee < 0 || knee_bound_[side].empty() || !knee_bound_[side][f]) continue;
      // A joint's world position: its skinning matrix carries its rest position there.
      const glm::vec4 rest = glm::inverse(rest_inverse_[knee])[3];
      const glm::vec3 moved = glm::vec3(skin(f + 1)[knee] * rest - skin(f)[knee] * rest);
      steps[f][side] = glm::vec2(moved.x, moved.z);
    }
  }
  return steps;
}

std::vector<glm::vec2> BodyContacts::hold(const std::vector<std::uint8_t>& held,
                                          const std::vector<glm::vec2>& step) const {
  // Frame by frame: in a run of held frames the hold goes on by each step; out of it, the
  // value the last run ended with fades linearly to zero over max(kFade, |value| / speed), and
  // a new run starts from what is left of it (so nothing jumps at a touchdown or lift-off).
  std::vector<glm::vec2> values(frame_count_, glm::vec2(0.0f));
  glm::vec2 ended(0.0f);
  int ended_at = -1;
  double fade = kFade;
  for (int f = 0; f < frame_count_; ++f) {
    if (held[f] && f > 0 && held[f - 1]) {
      values[f] = values[f - 1] + step[f - 1];
    } else if (ended_at >= 0) {
      const double seconds = (f - ended_at) * frame_time_;
      values[f] = ended * static_cast<float>(std::max(0.0, 1.0 - seconds / fade));
    }
    if (held[f] && (f + 1 == frame_count_ || !held[f + 1])) {
      ended = values[f], ended_at = f;
      fade = std::max(kFade, double{glm::length(ended) / (kReturnSpeed * hip_height_)});
    }
  }
  return values;
}

glm::vec2 BodyContacts::at(const std::vector<glm::vec2>& values, double seconds) const {
  if (values.empty()) return glm::vec2(0.0f);
  const double position =
      std::clamp(seconds / frame_time_, 0.0, static_cast<double>(frame_count_ - 1));
  const int f0 = static_cast<int>(std::floor(position));
  const int f1 = std::min(f0 + 1, frame_count_ - 1);
  return glm::mix(values[f0], values[f1], static_cast<float>(position - f0));
}

bool BodyContacts::any() const {
  for (const PartTrack& track : parts_)
    if (std::find(track.contact.begin(), track.contact.end(), 1) != track.contact.end())
      return true;
  return false;
}

void BodyContacts::hold_root(double seconds, deform::Pose& pose) const {
  if (!holds_root_) return;
  const glm::vec2 shift = at(root_shift_, seconds);
  pose.root_translation.x += shift.x;
  pose.root_translation.z += shift.y;
}

void BodyContacts::plan_limbs(const std::function<deform::Pose(int)>& frame_pose,
                              const std::function<bool(int, int)>& foot_planted,
                              const std::function<bool(int, int)>& raised) {
  const auto whole = [](LimbJoints limb, bool end) {
    return limb.upper >= 0 && limb.lower >= 0 && (!end || limb.end >= 0);
  };
  std::array<bool, kPartCount> limbs{};
  for (int side = 0; side < 2; ++side) {
    limbs[kLeftKnee + side] = whole(legs_[side], false);
    limbs[kLeftArm + side] = whole(arms_[side], false);
    limbs[kLeftHand + side] = whole(arms_[side], true);
  }
  const auto steps = contact_steps(frame_pose, limbs);
  for (int part = 0; part < kPartCount; ++part) {
    limb_shift_[part].clear();
    if (!limbs[part]) continue;
    // A knee whose foot is planted is foot planting's: the feet win.
    const int knee_side = part == kLeftKnee ? 0 : part == kRightKnee ? 1 : -1;
    std::vector<std::uint8_t> held = parts_[part].contact;
    // An arm the body floor raises is held after the raise (plan_raised_arms).
    if (const std::vector<std::uint8_t> later = raised_runs(part, raised); !later.empty())
      for (int f = 0; f < frame_count_; ++f) held[f] = held[f] && !later[f];
    std::vector<glm::vec2> step(frame_count_, glm::vec2(0.0f));
    bool any = false;
    for (int f = 0; f < frame_count_; ++f) {
      if (knee_side >= 0 && held[f] && foot_planted(knee_side, f)) held[f] = 0;
      if (steps[f][part]) step[f] = -*steps[f][part];
      any = any || held[f];
    }
    if (!any) continue;
    limb_shift_[part] = hold(held, step);
    limit_rate(limb_shift_[part]);
    holds_limbs_ = true;
    // A knee's hold tapers to nothing within kFade of its foot's planted frames (none there).
    if (knee_side < 0) continue;
    const std::vector<int> distance = planted_distance(knee_side, foot_planted);
    for (int f = 0; f < frame_count_; ++f)
      limb_shift_[part][f] *= static_cast<float>(distance[f]) / static_cast<float>(taper());
  }
}

void BodyContacts::plan_raised_arms(const std::function<deform::Pose(int)>& frame_pose,
                                    const std::function<bool(int, int)>& raised) {
  std::array<bool, kPartCount> arms{};
  for (int side = 0; side < 2; ++side)
    arms[kLeftArm + side] = arms_[side].upper >= 0 && arms_[side].lower >= 0;
  for (std::vector<glm::vec2>& shift : raised_arm_shift_) shift.clear();
  holds_raised_arms_ = false;
  const auto steps = contact_steps(frame_pose, arms);
  for (int part = 0; part < kPartCount; ++part) {
    if (!arms[part]) continue;
    const std::vector<std::uint8_t> held = raised_runs(part, raised);
    if (std::find(held.begin(), held.end(), 1) == held.end()) continue;
    std::vector<glm::vec2> step(frame_count_, glm::vec2(0.0f));
    for (int f = 0; f < frame_count_; ++f)
      if (steps[f][part]) step[f] = -*steps[f][part];
    raised_arm_shift_[part] = hold(held, step);
    limit_rate(raised_arm_shift_[part]);
    // It tapers linearly to nothing within kFade of a frame where that hand rests (the hand's
    // hold before the lift keeps the hand there, as a knee's beside its planted foot) or the
    // arm is not raised (only the raise keeps a held arm off the floor: the lift was built
    // without this hold).
    const int side = part - kLeftArm;
    const std::vector<std::uint8_t>& hand = parts_[kLeftHand + side].contact;
    const std::vector<int> distance = planted_distance(
        side, [&](int s, int frame) { return hand[frame] != 0 || !raised(s, frame); });
    for (int f = 0; f < frame_count_; ++f)
      raised_arm_shift_[part][f] *= static_cast<float>(distance[f]) / static_cast<float>(taper());
    holds_raised_arms_ = true;
  }
}

std::vector<std::uint8_t> BodyContacts::raised_runs(
    int part, const std::function<bool(int, int)>& raised) const {
  const int side = part == kLeftArm ? 0 : part == kRightArm ? 1 : -1;
  if (side < 0 || !raised) return {};
  const std::vector<std::uint8_t>& contact = parts_[part].contact;
  std::vector<std::uint8_t> runs(frame_count_, 0);
  for (int first = 0; first < frame_count_;) {
    if (!contact[first]) {
      ++first;
      continue;
    }
    int last = first;
    bool any = raised(side, first);
    for (; last + 1 < frame_count_ && contact[last + 1]; ++last)
      any = any || raised(side, last + 1);
    // Where the hand rests too, the hands' and elbows' holds before the lift keep the hand
    // (the raise lifts its wrist straight up); holding the elbow after the raise as well
    // moved the held hand (the male's 0.1 -> 4.2 cm).
    const std::vector<std::uint8_t>& hand = parts_[kLeftHand + side].contact;
    any = any &&
          std::find(hand.begin() + first, hand.begin() + last + 1, 1) == hand.begin() + last + 1;
    if (any) std::fill(runs.begin() + first, runs.begin() + last + 1, 1);
    first = last + 1;
  }
  return runs;
}

int BodyContacts::taper() const {
  return std::max(1, static_cast<int>(std::lround(kFade / frame_time_)));
}

std::vector<int> BodyContacts::planted_distance(
    int side, const std::function<bool(int, int)>& foot_planted) const {
  const int most = taper();
  std::vector<int> distance(frame_count_, most);
  for (int f = 0, last = -most; f < frame_count_; ++f) {
    if (foot_planted(side, f)) last = f;
    distance[f] = std::min(most, f - last);
  }
  for (int f = frame_count_ - 1, next = frame_count_ - 1 + most; f >= 0; --f) {
    if (foot_planted(side, f)) next = f;
    distance[f] = std::min(distance[f], next - f);
  }
  return distance;
}

bool BodyContacts::knee_bound(int frame) const {
  return (!knee_bound_[0].empty() && knee_bound_[0][frame]) ||
         (!knee_bound_[1].empty() && knee_bound_[1][frame]);
}

void BodyContacts::hold_raised_arms(double seconds, const BodyFloor& body_floor,
                                    deform::Pose& pose) const {
  if (!holds_raised_arms_) return;
  std::vector<glm::mat4> world(skeleton_.joints.size()), skin(skeleton_.joints.size());
  for (int side = 0; side < 2; ++side) {
    const int part = kLeftArm + side;
    if (raised_arm_shift_[part].empty()) continue;
    const glm::vec2 shift = at(raised_arm_shift_[part], seconds);
    if (shift == glm::vec2(0.0f)) continue;
    // The part's lowest point as raised, and where its hold puts it across.
    const auto skinned = [&] {
      deform::forward_kinematics(skeleton_, pose, world);
      deform::skinning_matrices(world, rest_inverse_, skin);
    };
    skinned();
    int lowest = -1;
    float y = std::numeric_limits<float>::infinity();
    for (const int i : parts_[part].samples)
      if (const float h = samples_->height(i, skin); h < y) y = h, lowest = i;
    if (lowest < 0) continue;
    const glm::vec3 start = samples_->position(lowest, skin);
    const glm::vec2 target = glm::vec2(start.x, start.z) + shift;
    // Moved across, then raised again where that dipped it, which may move it across (an arm
    // swung up about its shoulder): what is left is moved again (kRaisedHoldPasses).
    for (int pass = 0; pass < kRaisedHoldPasses; ++pass) {
      const glm::vec3 now = samples_->position(lowest, skin);
      const glm::vec2 left = target - glm::vec2(now.x, now.z);
      if (glm::length(left) < 1e-4f) break;  // 0.1 mm
      move_limb_middle(skeleton_, arms_[side], glm::vec3(left.x, 0.0f, left.y), world,
                       world_rotations(skeleton_, pose), pose);
      body_floor.raise_arms(seconds, pose);
      skinned();
    }
  }
}

void BodyContacts::hold_limbs(double seconds, deform::Pose& pose) const {
  if (!holds_limbs_) return;
  std::vector<glm::mat4> world(skeleton_.joints.size());
  const auto shift = [&](int part) {
    const glm::vec2 s =
        limb_shift_[part].empty() ? glm::vec2(0.0f) : at(limb_shift_[part], seconds);
    return glm::vec3(s.x, 0.0f, s.y);
  };
  // Knees and elbows first (the upper bone swings; what hangs below moves with it), then the
  // wrists (two-bone IK to where the hand's hold puts them: the hands win over the elbows).
  deform::forward_kinematics(skeleton_, pose, world);
  std::vector<glm::quat> rotation = world_rotations(skeleton_, pose);
  std::array<glm::vec3, 2> wrist_before{};
  for (int side = 0; side < 2; ++side)
    if (arms_[side].end >= 0) wrist_before[side] = glm::vec3(world[arms_[side].end][3]);
  for (int side = 0; side < 2; ++side) {
    if (const glm::vec3 knee = shift(kLeftKnee + side); knee != glm::vec3(0.0f))
      move_limb_middle(skeleton_, legs_[side], knee, world, rotation, pose);
    if (const glm::vec3 elbow = shift(kLeftArm + side); elbow != glm::vec3(0.0f))
      move_limb_middle(skeleton_, arms_[side], elbow, world, rotation, pose);
  }
  if (limb_shift_[kLeftHand].empty() && limb_shift_[kRightHand].empty()) return;
  deform::forward_kinematics(skeleton_, pose, world);
  rotation = world_rotations(skeleton_, pose);
  for (int side = 0; side < 2; ++side) {
    if (limb_shift_[kLeftHand + side].empty() || arms_[side].end < 0) continue;
    // Across to where the hand's hold puts it, from wherever the elbow's hold left it (the
    // forearm turned where the elbow would have folded past the clip's bend).
    glm::vec3 wrist =
        wrist_before[side] + shift(kLeftHand + side) - glm::vec3(world[arms_[side].end][3]);
    wrist.y = 0.0f;
    // A straight arm bends at the elbow upwards, off the floor. (1e-6 m: rounding.)
    if (glm::length(wrist) > 1e-6f)
      move_limb_end(skeleton_, arms_[side], wrist, world, rotation, glm::vec3(0.0f, -1.0f, 0.0f),
                    kSoftReach, pose);
  }
}

std::vector<BodyContacts::ContactSlide> BodyContacts::contact_slides(
    const std::function<deform::Pose(int)>& frame_pose) const {
  std::array<bool, kPartCount> every;
  every.fill(true);
  const auto steps = contact_steps(frame_pose, every);
  std::vector<ContactSlide> slides;
  for (int p = 0; p < kPartCount; ++p) {
    const std::vector<std::uint8_t>& contact = parts_[p].contact;
    for (int first = 0; first < frame_count_;) {
      if (!contact[first]) {
        ++first;
        continue;
      }
      ContactSlide slide{p, first, first, 0.0f};
      for (; slide.last + 1 < frame_count_ && contact[slide.last + 1]; ++slide.last)
        if (steps[slide.last][p]) slide.slide += glm::length(*steps[slide.last][p]);
      slides.push_back(slide);
      first = slide.last + 1;
    }
  }
  return slides;
}

}  // namespace sweepd::motion
