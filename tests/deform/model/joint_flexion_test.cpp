// Joint flexion (deform/model/joint_flexion.h): a limb posed by its anatomical angle lands at that
// angle, whatever its rest pose's bend and its parent's rest rotation.
#include "deform/model/joint_flexion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// The flexion of `joint` in a posed skeleton, from its world joint positions.
float posed_flexion_degrees(const Skeleton& skeleton, const Pose& pose, int joint, glm::vec3 axis) {
  std::vector<glm::mat4> world(skeleton.size());
  forward_kinematics(skeleton, pose, world);
  auto at = [&](int k) { return glm::vec3(world[k][3]); };
  const glm::vec3 upper = at(joint) - at(skeleton.joints[joint].parent);
  const glm::vec3 lower = at(skeleton.children(joint).front()) - at(joint);
  axis = glm::normalize(axis);
  const glm::vec3 u = upper - glm::dot(upper, axis) * axis,
                  l = lower - glm::dot(lower, axis) * axis;
  return glm::degrees(std::atan2(glm::dot(glm::cross(u, l), axis), glm::dot(u, l)));
}

// shoulder → elbow → wrist; the shoulder turned 30° about z at rest and the elbow bent 20°
// about z, so the forearm starts 20° from the upper arm's line.
Skeleton bent_arm() {
  Skeleton s;
  s.joints.push_back({"shoulder",
                      -1,
                      {0, 1, 0},
                      glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 0, 1)),
                      glm::vec3(1)});
  s.joints.push_back({"elbow",
                      0,
                      {0.3f, 0, 0},
                      glm::angleAxis(glm::radians(20.0f), glm::vec3(0, 0, 1)),
                      glm::vec3(1)});
  s.joints.push_back({"wrist", 1, {0.25f, 0, 0}, glm::quat(1, 0, 0, 0), glm::vec3(1)});
  return s;
}

TEST(JointFlexion, RestBendIsMeasuredAndTheTargetAngleReached) {
  const Skeleton arm = bent_arm();
  const glm::vec3 z(0, 0, 1);
  // Exact up to float round-off of the world matrices.
  EXPECT_NEAR(rest_flexion_degrees(arm, 1, z), 20.0f, 1e-4f);
  EXPECT_NEAR(rest_flexion_degrees(arm, 1, -z), -20.0f, 1e-4f);
  for (float target : {0.0f, 90.0f, 150.0f, -10.0f}) {
    Pose pose = rest_pose(arm);
    flex_joint(arm, pose, 1, z, target);
    EXPECT_NEAR(posed_flexion_degrees(arm, pose, 1, z), target, 1e-3f) << target;
    // The turn is about the world axis: the forearm stays in the plane orthogonal to it.
    std::vector<glm::mat4> world(arm.size());
    forward_kinematics(arm, pose, world);
    EXPECT_NEAR(world[2][3].z, 0.0f, 1e-6f) << target;
  }
}

// turn_joint turns any joint, a root too, by the stated angle about a world axis: the link below
// it turns by that much in world space (exact up to float round-off).
TEST(JointFlexion, TurnJointTurnsTheLinkBelowAboutTheWorldAxis) {
  const Skeleton arm = bent_arm();
  std::vector<glm::mat4> rest(arm.size()), posed(arm.size());
  forward_kinematics(arm, rest_pose(arm), rest);
  const glm::vec3 axis = glm::normalize(glm::vec3(1, 1, 0));
  for (int joint : {0, 1}) {
    Pose pose = rest_pose(arm);
    turn_joint(arm, pose, joint, axis, 40.0f);
    forward_kinematics(arm, pose, posed);
    const glm::vec3 link_rest = glm::vec3(rest[joint + 1][3]) - glm::vec3(rest[joint][3]);
    const glm::vec3 link_posed = glm::vec3(posed[joint + 1][3]) - glm::vec3(posed[joint][3]);
    const glm::vec3 expected = glm::angleAxis(glm::radians(40.0f), axis) * link_rest;
    EXPECT_NEAR(glm::distance(link_posed, expected), 0.0f, 1e-6f) << joint;
  }
}

TEST(JointFlexion, NeedsAParentAndAChild) {
  const Skeleton arm = bent_arm();
  Pose pose = rest_pose(arm);
  EXPECT_THROW(flex_joint(arm, pose, 0, {0, 0, 1}, 90.0f), std::invalid_argument);
  EXPECT_THROW(rest_flexion_degrees(arm, 2, {0, 0, 1}), std::invalid_argument);
}

TEST(JointFlexion, SharedMaleElbowIsBentAtRest) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  const int elbow = model.skeleton.find("LeftForeArm"), knee = model.skeleton.find("LeftLeg");
  const glm::vec3 elbow_axis = test::left_elbow_flexion_axis(model);
  const float elbow_rest = rest_flexion_degrees(model.skeleton, elbow, elbow_axis);
  const float knee_rest = rest_flexion_degrees(model.skeleton, knee, {1, 0, 0});
  std::printf("shared male at rest: left elbow flexed %.1f°, left knee %.1f°\n", elbow_rest,
              knee_rest);
  // Its A-pose holds the forearms forward (46.4° from the joint positions) and the knees
  // nearly straight; a turn of 150° from rest would be a 196° flexion.
  EXPECT_NEAR(elbow_rest, 46.4f, 0.5f);
  EXPECT_NEAR(knee_rest, 6.0f, 1.0f);
  Pose pose = rest_pose(model.skeleton);
  flex_joint(model.skeleton, pose, elbow, elbow_axis, 150.0f);
  EXPECT_NEAR(posed_flexion_degrees(model.skeleton, pose, elbow, elbow_axis), 150.0f, 1e-2f);
}

}  // namespace
}  // namespace sweepd::deform
