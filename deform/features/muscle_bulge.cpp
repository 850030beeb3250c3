#include "deform/features/muscle_bulge.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "deform/model/joint_turn_from_rest.h"

namespace sweepd::deform {

float bulge_activation(float turn_radians, const MuscleBulgeOptions& options) {
  const float x = std::clamp(turn_radians / glm::radians(options.full_flexion_degrees), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

void apply_muscle_bulge(const BoundModel& bound, int s, std::span<const glm::quat> joint_rotation,
                        const MuscleBulgeOptions& options, std::span<KeyEllipse> keys) {
  const BoundSweep& sweep = bound.sweeps[s];
  int muscle_link = -1, bending_joint = -1;
  float gain = 0.0f, facing = 1.0f;  // the calf lies behind the shin: facing -1
  const RigMap& rig = bound.rig;
  if (options.biceps && (sweep.part == BodyPart::kLeftArm || sweep.part == BodyPart::kRightArm)) {
    const ArmJoints& arm = sweep.part == BodyPart::kLeftArm ? rig.left_arm : rig.right_arm;
    muscle_link = arm.upper, bending_joint = arm.lower, gain = options.biceps_gain;
  } else if (options.calves &&
             (sweep.part == BodyPart::kLeftLeg || sweep.part == BodyPart::kRightLeg)) {
    const LegJoints& leg = sweep.part == BodyPart::kLeftLeg ? rig.left_leg : rig.right_leg;
    muscle_link = leg.lower, bending_joint = leg.lower, gain = options.calf_gain, facing = -1.0f;
  }
  if (muscle_link < 0 || bending_joint < 0) return;
  const float activation = bulge_activation(
      joint_turn_from_rest(bound.model.skeleton, joint_rotation, bending_joint), options);
  if (activation == 0.0f) return;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const KeyAnchor& anchor = sweep.anchors[k];
    if (anchor.joint != muscle_link || anchor.is_joint_key()) continue;
    // The muscle's side in the key's rest frame: the in-plane axis nearest `front` (or behind).
    const glm::mat3 rest_frame = glm::mat3_cast(sweep.rest_keys[k].orientation);
    const float along_a = facing * glm::dot(rest_frame[0], options.front);
    const float along_b = facing * glm::dot(rest_frame[1], options.front);
    const bool use_a = std::abs(along_a) >= std::abs(along_b);
    const float side = (use_a ? along_a : along_b) >= 0.0f ? 1.0f : -1.0f;
    const float profile = std::sin(std::numbers::pi_v<float> * anchor.fraction);
    float& half_axis = use_a ? keys[k].a : keys[k].b;
    const float delta = gain * half_axis * activation * profile;
    half_axis += delta;
    const glm::vec3 axis = glm::mat3_cast(keys[k].orientation)[use_a ? 0 : 1];
    keys[k].centre += side * delta * axis;
  }
}

}  // namespace sweepd::deform
