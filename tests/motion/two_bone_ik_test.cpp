// Holding a limb's middle joint across (motion/two_bone_ik.h, move_limb_middle: an elbow or knee
// resting on the floor held where it touched down): the upper bone swings about its root and
// the lower bone keeps its world rotation, but never so far that the middle joint folds past the
// clip's own bend. A hand-made arm (shoulder at the origin, upper arm 0.3 m along +x, forearm
// 0.25 m), its elbow bent 90° (the forearm along -z, horizontal, as lying on the floor):
// - held towards the forearm's side the swing unfolds the elbow (90° -> 71.6°): the forearm
//   keeps its world rotation, the wrist moves with the elbow (1e-5 m: float round-off);
// - held the other way the swing would fold it to 108.4°: the elbow still goes where the hold
//   puts it and the bend stays the clip's 90° (0.01°: round-off of acos near 90°).
#include "motion/two_bone_ik.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deform/model/forward_kinematics.h"

namespace sweepd::motion {
namespace {

deform::Skeleton arm() {
  deform::Skeleton skeleton;
  skeleton.joints.push_back({"shoulder", -1, glm::vec3(0.0f)});
  skeleton.joints.push_back({"elbow", 0, glm::vec3(0.3f, 0.0f, 0.0f)});
  skeleton.joints.push_back({"wrist", 1, glm::vec3(0.25f, 0.0f, 0.0f)});
  return skeleton;
}

struct Arm {
  glm::vec3 shoulder, elbow, wrist;
  float bend_degrees;  // between the upper arm and the forearm: 0 straight
};

Arm posed(const deform::Skeleton& skeleton, const deform::Pose& pose) {
  std::vector<glm::mat4> world(skeleton.joints.size());
  deform::forward_kinematics(skeleton, pose, world);
  Arm arm{glm::vec3(world[0][3]), glm::vec3(world[1][3]), glm::vec3(world[2][3]), 0.0f};
  const glm::vec3 upper = glm::normalize(arm.elbow - arm.shoulder);
  const glm::vec3 lower = glm::normalize(arm.wrist - arm.elbow);
  arm.bend_degrees = glm::degrees(std::acos(std::clamp(glm::dot(upper, lower), -1.0f, 1.0f)));
  return arm;
}

// The arm with its elbow held across by `shift`.
Arm held(glm::vec3 shift, Arm& before) {
  const deform::Skeleton skeleton = arm();
  deform::Pose pose = deform::rest_pose(skeleton);
  // +x turned 90° about +y goes to -z: the forearm lies along -z.
  pose.local_rotations[1] = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  before = posed(skeleton, pose);
  std::vector<glm::mat4> world(skeleton.joints.size());
  deform::forward_kinematics(skeleton, pose, world);
  move_limb_middle(skeleton, {0, 1, 2}, shift, world, world_rotations(skeleton, pose), pose);
  return posed(skeleton, pose);
}

TEST(MoveLimbMiddle, AnElbowHeldTowardsItsForearmUnfoldsWithTheForearmKeptAsItWas) {
  Arm before;
  const Arm after = held(glm::vec3(0.0f, 0.0f, -0.1f), before);
  ASSERT_NEAR(before.bend_degrees, 90.0f, 0.01f);
  EXPECT_NEAR(after.bend_degrees, glm::degrees(std::acos(0.1f / std::sqrt(0.1f))), 0.01f);
  const glm::vec3 elbow_move = after.elbow - before.elbow, wrist_move = after.wrist - before.wrist;
  EXPECT_NEAR(glm::distance(elbow_move, wrist_move), 0.0f, 1e-5f);
  // The elbow swung towards where the hold puts it (round the shoulder: 0.3 m from it).
  const glm::vec3 swung = glm::normalize(glm::vec3(0.3f, 0.0f, -0.1f)) * 0.3f;
  EXPECT_NEAR(glm::distance(after.elbow, swung), 0.0f, 1e-5f);
}

TEST(MoveLimbMiddle, AnElbowHeldAwayFromItsForearmKeepsTheClipsBend) {
  Arm before;
  const Arm after = held(glm::vec3(0.0f, 0.0f, 0.1f), before);
  EXPECT_NEAR(after.bend_degrees, 90.0f, 0.01f) << "folded past the clip's 90°";
  // The elbow swung towards where the hold puts it (round the shoulder: 0.3 m from it).
  const glm::vec3 swung = glm::normalize(glm::vec3(0.3f, 0.0f, 0.1f)) * 0.3f;
  EXPECT_NEAR(glm::distance(after.elbow, swung), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(after.wrist, after.elbow), 0.25f, 1e-5f);
  EXPECT_NEAR(after.wrist.y, before.wrist.y, 1e-5f) << "the forearm stays horizontal";
}

}  // namespace
}  // namespace sweepd::motion
