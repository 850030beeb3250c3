#include "motion/body_floor.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deform/model/forward_kinematics.h"
#include "motion/contact_timing.h"
#include "motion/two_bone_ik.h"

namespace sweepd::motion {

BodyFloor BodyFloor::build(const deform::Model& model,
                           std::shared_ptr<const BodySamples> samples_in,
                           const std::vector<bool>& feet, float floor, int frame_count,
                           double frame_time, const std::function<deform::Pose(int)>& frame_pose,
                           std::span<const int> group, std::span<const std::uint8_t> arms_through,
                           std::array<LimbJoints, 2> arms) {
  BodyFloor body;
  body.frame_time_ = frame_time;
  body.lift_.assign(std::max(frame_count, 1), 0.0f);
  body.samples_ = std::move(samples_in);
  const BodySamples& samples = *body.samples_;
  if (arms_through.size() == static_cast<std::size_t>(frame_count) &&
      std::any_of(arms_through.begin(), arms_through.end(), [](std::uint8_t a) { return a; })) {
    // An arm the clip pushes through its floor within kEase holds nothing up either: else its
    // need, eased kEase either side, lifts the body around the frames where it rises.
    const int reach = std::max(1, static_cast<int>(std::ceil(kEase / frame_time)));
    body.arms_through_.assign(frame_count, 0);
    for (int f = 0; f < frame_count; ++f)
      for (int g = std::max(0, f - reach); g <= std::min(frame_count - 1, f + reach); ++g)
        body.arms_through_[f] |= arms_through[g];
    body.skeleton_ = model.skeleton;
    body.rest_inverse_ = deform::world_rest_inverse_matrices(model.skeleton);
    body.arms_ = arms;
    body.arm_lowest_ = floor + kClearance;
  }
  std::vector<float> lowest_allowed;
  std::vector<int> group_of, arm_of;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int joint = samples.joint(i);
    lowest_allowed.push_back(feet.at(joint) ? floor - kSoleTolerance : floor + kClearance);
    group_of.push_back(group.empty() ? -1 : group[i]);
    body.groups_ = std::max(body.groups_, group_of.back() + 1);
    arm_of.push_back(-1);
    for (int side = 0; side < 2 && !body.arms_through_.empty(); ++side)
      if (arms[side].upper >= 0 && is_at_or_below(model.skeleton, joint, arms[side].upper)) {
        arm_of.back() = side;
        body.arm_samples_[side].push_back(static_cast<int>(i));
      }
  }
  if (samples.size() == 0 || frame_count < 1) return body;
  body.lowest_.assign(static_cast<std::size_t>(frame_count) * body.groups_, Lowest{});
  const std::vector<glm::mat4> rest_inverse = deform::world_rest_inverse_matrices(model.skeleton);
  std::vector<glm::mat4> world(model.skeleton.size()), skinning(model.skeleton.size());
  std::vector<float> need(frame_count, 0.0f);
  std::vector<std::array<float, 2>> arm_need(frame_count, {0.0f, 0.0f});  // before the lift
  for (int f = 0; f < frame_count; ++f) {
    deform::forward_kinematics(model.skeleton, frame_pose(f), world);
    deform::skinning_matrices(world, rest_inverse, skinning);
    Lowest* lowest = body.lowest_.data() + static_cast<std::size_t>(f) * body.groups_;
    // An arm the clip pushes through its floor beside its lying torso holds nothing up.
    const int free_arms = body.arms_through_.empty() ? 0 : body.arms_through_[f];
    float deepest = 0.0f;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const float y = samples.height(i, skinning);
      const float depth = lowest_allowed[i] - samples.swept_height(i, skinning);
      if (arm_of[i] >= 0 && (free_arms & (1 << arm_of[i])))
        arm_need[f][arm_of[i]] = std::max(arm_need[f][arm_of[i]], depth);
      else
        deepest = std::max(deepest, depth);
      if (const int g = group_of[i]; g >= 0 && y - floor < lowest[g].height)
        lowest[g] = {y - floor, static_cast<int>(i)};
    }
    need[f] = deepest;
  }
  // Each need spreads kEase either side, falling linearly: the lift is their upper envelope.
  const int reach = std::max(1, static_cast<int>(std::ceil(kEase / frame_time)));
  for (int f = 0; f < frame_count; ++f) {
    if (need[f] <= 0.0f) continue;
    for (int g = std::max(0, f - reach); g <= std::min(frame_count - 1, f + reach); ++g) {
      const double gap = std::abs(g - f) * frame_time;
      const float share = static_cast<float>(std::max(0.0, 1.0 - gap / kEase));
      body.lift_[g] = std::max(body.lift_[g], need[f] * share);
    }
  }
  for (int f = 0; f < frame_count; ++f)
    for (const float arm : arm_need[f])
      body.largest_arm_rise_ = std::max(body.largest_arm_rise_, arm - body.lift_[f]);
  return body;
}

void BodyFloor::raise_arm(int side, deform::Pose& pose) const {
  const LimbJoints& arm = arms_[side];
  if (arm_samples_[side].empty()) return;
  const BodySamples& samples = *samples_;
  std::vector<glm::mat4> world(skeleton_.size()), skinning(skeleton_.size());
  // Twice: raised, another sample of the arm may become its lowest.
  for (int pass = 0; pass < 2; ++pass) {
    deform::forward_kinematics(skeleton_, pose, world);
    deform::skinning_matrices(world, rest_inverse_, skinning);
    int deepest = -1;
    float lowest = arm_lowest_;
    for (const int i : arm_samples_[side])
      if (const float y = samples.swept_height(i, skinning); y < lowest) lowest = y, deepest = i;
    if (deepest < 0) return;
    const float rise = arm_lowest_ - lowest;
    const std::vector<glm::quat> rotation = world_rotations(skeleton_, pose);
    // The hand lowest: the wrist goes straight up (the elbow bends), so that a hand resting on
    // the floor stays where it rests.
    if (arm.lower >= 0 && arm.end >= 0 &&
        is_at_or_below(skeleton_, samples.joint(deepest), arm.end)) {
      move_limb_end(skeleton_, arm, glm::vec3(0.0f, rise, 0.0f), world, rotation,
                    glm::vec3(0.0f, -1.0f, 0.0f), kSoftReach, pose);
      continue;
    }
    // Else the arm swings up about its upper joint, in the vertical plane through that sample,
    // until the sample is as high as the floor allows (as far as the arm's length reaches).
    const glm::vec3 reach = samples.position(deepest, skinning) - glm::vec3(world[arm.upper][3]);
    const glm::vec3 axis = glm::cross(reach, glm::vec3(0.0f, 1.0f, 0.0f));
    const float length = glm::length(reach);
    if (!(length > 0.0f) || glm::length(axis) < 1e-6f * length) return;  // straight down
    const float from = std::asin(std::clamp(reach.y / length, -1.0f, 1.0f));
    const float to = std::asin(std::clamp((reach.y + rise) / length, -1.0f, 1.0f));
    const glm::quat swing = glm::angleAxis(to - from, glm::normalize(axis));
    const int parent = skeleton_.joints[arm.upper].parent;
    const glm::quat above = parent < 0 ? glm::quat(1.0f, 0.0f, 0.0f, 0.0f) : rotation[parent];
    pose.local_rotations[arm.upper] =
        glm::normalize(glm::inverse(above) * swing * rotation[arm.upper]);
  }
}

BodyFloor::Lowest BodyFloor::lowest(int group, int frame) const {
  Lowest low = lowest_.at(static_cast<std::size_t>(frame) * groups_ + group);
  low.height += lift_[frame];
  return low;
}

void BodyFloor::apply(double seconds, deform::Pose& pose) const {
  const int last = static_cast<int>(lift_.size()) - 1;
  const double position = std::clamp(seconds / frame_time_, 0.0, static_cast<double>(last));
  const int f0 = static_cast<int>(std::floor(position));
  const int f1 = std::min(f0 + 1, last);
  pose.root_translation.y += glm::mix(lift_[f0], lift_[f1], static_cast<float>(position - f0));
  raise_arms(seconds, pose);
}

void BodyFloor::raise_arms(double seconds, deform::Pose& pose) const {
  if (arms_through_.empty()) return;
  const int last = static_cast<int>(lift_.size()) - 1;
  const double position = std::clamp(seconds / frame_time_, 0.0, static_cast<double>(last));
  const int free_arms = arms_through_[static_cast<int>(std::lround(position))];
  for (int side = 0; side < 2; ++side)
    if (free_arms & (1 << side)) raise_arm(side, pose);
}

float BodyFloor::largest_lift() const {
  return lift_.empty() ? 0.0f : *std::max_element(lift_.begin(), lift_.end());
}

}  // namespace sweepd::motion
