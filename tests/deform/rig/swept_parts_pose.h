// Test helper: a pose that bends every swept part a rig map has — the spine, the neck, both
// shoulders and elbows, and, where the legs are there, the left hip and knee and the right hip.
// Axes are world axes at each joint (the shared male's and the mannequin's rest frames are
// world-aligned); angles are large enough that every sweep's keys move.
#pragma once

#include <glm/gtc/quaternion.hpp>

#include "deform/model/pose.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform::test {

inline Pose swept_parts_pose(const Skeleton& skeleton, const RigMap& rig) {
  Pose pose = rest_pose(skeleton);
  auto turn = [&](int joint, glm::vec3 axis, float degrees) {
    pose.local_rotations[joint] = glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
  };
  turn(rig.torso.chain[1], {1, 0, 0.3f}, 20.0f);
  if (rig.has_head()) turn(rig.neck.chain[0], {0.2f, 1, 0}, 35.0f);
  turn(rig.left_arm.upper, {0, 0, 1}, 40.0f);
  turn(rig.right_arm.upper, {1, 0, 0}, -50.0f);
  turn(rig.left_arm.lower, {0, 1, 0}, 70.0f);
  turn(rig.right_arm.lower, {0, 1, 0}, -60.0f);
  if (!rig.left_leg.absent()) {
    turn(rig.left_leg.upper, {1, 0, 0}, -60.0f);
    turn(rig.left_leg.lower, {1, 0, 0}, 80.0f);
  }
  if (!rig.right_leg.absent()) turn(rig.right_leg.upper, {0, 0, 1}, 25.0f);
  return pose;
}

}  // namespace sweepd::deform::test
