// Body floor: no part of a retargeted body below the model's floor (issue 48 item 3).
//
// Foot planting (foot_planting.h) puts the feet on the floor where the clip plants them. Other
// parts that the clip puts on its floor (knees when kneeling, hips and back when sitting or
// knocked down, hands when crawling) land where the model's proportions put them: a body whose
// arms are longer than the clip's, relative to its legs, pushes its hands through the floor; one
// whose hips sit lower pushes its seat. Here the whole body rises, on every frame, as far as its
// deepest part is below the floor, so that part rests on it.
//
// How: the rest mesh is sampled (motion/body_samples.h: per joint, and per band of the skin
// blended across a joint, the vertices furthest along 64 directions; a few thousand samples
// skinned by linear blending). A frame's
// need is how far its lowest sample's swept height (body_samples.h: moved out from a bent joint
// as the sweep keeps its volume, turned near it as the sweep's keys turn the skin, and across
// the bend's outside as a mitre; linear at the feet)
// lies below its height: the floor less
// kSoleTolerance for a foot's samples (foot planting puts the soles on the floor: they must not
// lift the body), the floor plus kClearance for every other part (the sweep's surface still runs
// up to about 0.9 cm below the swept heights where an elbow, knee, hip or back presses on the
// floor, 2.0 cm below the linear ones: the RiggedFigure without its middle spine joint, knocked
// down; tests/motion/humanoid_variants_test.cpp). The lift at a frame is
// the largest need within kEase either side, scaled down linearly with the distance in time, so
// the body never rises or settles faster than its deepest need per kEase and nothing pops.
// A body already above the floor is left where the clip and the feet put it (jumps stay jumps).
// An arm the clip pushes through its own floor beside its lying torso (`arms_through`,
// motion/clip_arms_through_floor.h) holds nothing up: its samples (each at or below the arm's
// upper joint) make no need on that frame or within kEase of it (else that need, eased, lifts the
// body around the frames where the arm comes up), so the torso comes down onto the floor (knocked
// down forwards, the clip's swinging hand 11-22 cm below its floor had held the model's chest 14-24
// cm up), and apply() raises the arm instead, until its lowest sample's swept height is at the
// floor plus kClearance: a hand lowest, its wrist straight up (two-bone IK: the elbow bends, a
// hand resting on the floor stays where it rests); else the arm swung up about its upper joint,
// its bend kept.
// Inputs:  model (rest mesh, skin), feet (per joint: a foot's or toe's, planted by foot
//          planting), floor (the rest mesh's lowest vertex height), the clip's frame count and
//          frame time, frame_pose (each clip frame's pose, feet planted), group (optional, per
//          sample: a group of samples, >= 0, whose lowest is kept per frame, or -1),
//          arms_through (optional, per clip frame: bit 1 the left arm, 2 the right, as
//          clip_arms_through_floor gives), arms (left, right: shoulder, elbow, wrist joints).
// Output:  apply() raises a pose's root by the lift at that time (interpolated between frames)
//          and raises each arm through the floor on that frame (the nearest clip frame's bits);
//          lowest(group, frame): that group's lowest sample (linearly blended: the contacts'
//          points move smoothly with the skin) on the clip frame, lifted (what
//          motion/body_contacts.h finds contacts by, with no second pass over the clip).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "deform/model/model.h"
#include "deform/model/pose.h"
#include "motion/body_samples.h"
#include "motion/two_bone_ik.h"

namespace sweepd::motion {

class BodyFloor {
 public:
  static constexpr float kSoleTolerance = 0.005f;  // m
  static constexpr float kClearance = 0.005f;      // m
  static constexpr double kEase = 0.15;            // s, as foot planting's

  // samples: the model's (body_samples.h); group: per sample, see the header.
  static BodyFloor build(const deform::Model& model, std::shared_ptr<const BodySamples> samples,
                         const std::vector<bool>& feet, float floor, int frame_count,
                         double frame_time, const std::function<deform::Pose(int)>& frame_pose,
                         std::span<const int> group = {},
                         std::span<const std::uint8_t> arms_through = {},
                         std::array<LimbJoints, 2> arms = {});

  // Raises `pose` (the pose of the clip at `seconds`, clamped to the clip) by the lift there,
  // and raises each arm the clip pushes through its floor there (see the header).
  void apply(double seconds, deform::Pose& pose) const;
  // The arms part of apply() alone: raises each arm the clip pushes through its floor at
  // `seconds` until it rests on the floor (a pose already lifted; body contacts hold such an
  // arm after the raise, then raise it again where the hold dipped it).
  void raise_arms(double seconds, deform::Pose& pose) const;
  // Whether apply() raises that side's arm (0 left, 1 right) on clip frame `frame`.
  bool raises_arm(int side, int frame) const {
    return !arms_through_.empty() && (arms_through_[frame] & (1 << side));
  }
  // The largest lift over the clip (m).
  float largest_lift() const;
  // About the most an arm the clip pushes through its floor rises off it (m: its samples'
  // depth below the floor on the lifted pose, before it rises).
  float largest_arm_rise() const { return largest_arm_rise_; }
  // The lift on clip frame `frame` (m).
  float lift(int frame) const { return lift_[frame]; }

  struct Lowest {
    float height = std::numeric_limits<float>::infinity();  // above the floor, lifted (m)
    int sample = -1;                                        // into samples(); -1: none
  };
  Lowest lowest(int group, int frame) const;
  int group_count() const { return groups_; }
  const std::shared_ptr<const BodySamples>& samples() const { return samples_; }

 private:
  std::vector<float> lift_;  // per clip frame (m)
  double frame_time_ = 0.0;
  int groups_ = 0;
  std::vector<Lowest> lowest_;  // per frame, per group: before the lift
  std::shared_ptr<const BodySamples> samples_;
  // Raises that side's arm until its samples rest on the floor (see the header).
  void raise_arm(int side, deform::Pose& pose) const;
  std::vector<std::uint8_t> arms_through_;       // per clip frame, or empty
  deform::Skeleton skeleton_;                    // for the arms' swing
  std::vector<glm::mat4> rest_inverse_;          // per joint
  std::array<LimbJoints, 2> arms_;               // left, right: shoulder, elbow, wrist
  std::array<std::vector<int>, 2> arm_samples_;  // per side: into samples_
  float arm_lowest_ = 0.0f;                      // the floor plus kClearance (m)
  float largest_arm_rise_ = 0.0f;                // m
};

}  // namespace sweepd::motion
