// Test pose: both elbows and both knees flexed to `degrees` from a bound model's rest pose (the
// right side mirrors the left), the bend the crease and shading tests put the skin through.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/model/joint_flexion.h"
#include "deform/model/pose.h"

namespace sweepd::deform::test {

inline Pose elbows_and_knees_flexed(const BoundModel& bound, float degrees) {
  const Skeleton& skeleton = bound.model.skeleton;
  const std::vector<glm::mat4> world = skeleton.world_rest_matrices();
  Pose pose = rest_pose(skeleton);
  for (const ArmJoints* arm : {&bound.rig.left_arm, &bound.rig.right_arm}) {
    const glm::vec3 upper = glm::vec3(world[arm->lower][3]) - glm::vec3(world[arm->upper][3]);
    flex_joint(skeleton, pose, arm->lower, glm::cross(glm::normalize(upper), glm::vec3(0, 0, 1)),
               degrees);
  }
  for (const LegJoints* leg : {&bound.rig.left_leg, &bound.rig.right_leg})
    flex_joint(skeleton, pose, leg->lower, glm::vec3(1, 0, 0), degrees);
  return pose;
}

}  // namespace sweepd::deform::test
