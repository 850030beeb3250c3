// Tests for deform::Pose (rest_pose, normalize_and_validate) and forward kinematics
// (forward_kinematics, skinning_matrices).
#include "deform/model/pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <numbers>
#include <vector>

#include "deform/model/forward_kinematics.h"

namespace sweepd::deform::pose_test {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Two trees: a three-joint arm with rest rotations and a scale, and a second root.
Skeleton two_tree_skeleton() {
  Skeleton skeleton;
  skeleton.joints.push_back({.name = "root",
                             .parent = -1,
                             .rest_translation = {0.0f, 1.0f, 0.0f},
                             .rest_rotation = glm::angleAxis(0.3f, glm::vec3(0, 1, 0)),
                             .rest_scale = glm::vec3(1.0f)});
  skeleton.joints.push_back({.name = "elbow",
                             .parent = 0,
                             .rest_translation = {1.0f, 0.0f, 0.0f},
                             .rest_rotation = glm::angleAxis(kPi / 6, glm::vec3(0, 0, 1)),
                             .rest_scale = glm::vec3(1.0f, 2.0f, 1.0f)});
  skeleton.joints.push_back({.name = "hand",
                             .parent = 1,
                             .rest_translation = {1.0f, 0.0f, 0.0f},
                             .rest_rotation = glm::angleAxis(-0.4f, glm::vec3(1, 0, 0)),
                             .rest_scale = glm::vec3(1.0f)});
  skeleton.joints.push_back({.name = "prop", .parent = -1, .rest_translation = {3.0f, 0.0f, 0.0f}});
  return skeleton;
}

float max_difference(const glm::mat4& a, const glm::mat4& b) {
  float difference = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) difference = std::max(difference, std::abs(a[c][r] - b[c][r]));
  return difference;
}

glm::vec3 origin(const glm::mat4& m) { return glm::vec3(m[3]); }

TEST(ForwardKinematics, RestPoseGivesTheWorldRestMatrices) {
  const Skeleton skeleton = two_tree_skeleton();
  const std::vector<glm::mat4> expected = skeleton.world_rest_matrices();
  std::vector<glm::mat4> world(skeleton.joints.size());
  forward_kinematics(skeleton, rest_pose(skeleton), world);
  // Same products in the same order, in float: only round-off may differ.
  for (int j = 0; j < skeleton.size(); ++j) EXPECT_LT(max_difference(world[j], expected[j]), 1e-6f);
}

TEST(ForwardKinematics, PoseRotationReplacesTheRestRotation) {
  const Skeleton skeleton = two_tree_skeleton();
  Pose pose = rest_pose(skeleton);
  pose.local_rotations[0] = glm::angleAxis(kPi / 2, glm::vec3(0, 0, 1));  // root: +X turns to +Y
  pose.local_rotations[1] = glm::identity<glm::quat>();  // elbow: its 30° rest bend is gone
  std::vector<glm::mat4> world(skeleton.joints.size());
  forward_kinematics(skeleton, pose, world);
  // Root at (0,1,0); elbow one unit along the turned +X = +Y; the unbent elbow carries the
  // hand straight on, with its rest scale (1,2,1) not touching the X offset. Float round-off.
  EXPECT_NEAR(glm::distance(origin(world[1]), glm::vec3(0, 2, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(origin(world[2]), glm::vec3(0, 3, 0)), 0.0f, 1e-6f);
}

TEST(ForwardKinematics, RootTranslationReplacesJointZerosAndShiftsOtherRoots) {
  const Skeleton skeleton = two_tree_skeleton();
  Pose pose = rest_pose(skeleton);
  pose.root_translation = {0.5f, 1.0f, -2.0f};  // a shift of (0.5, 0, -2) from the rest
  std::vector<glm::mat4> world(skeleton.joints.size());
  forward_kinematics(skeleton, pose, world);
  const std::vector<glm::mat4> rest = skeleton.world_rest_matrices();
  // Pure translations of exact binary fractions: round-off only.
  EXPECT_NEAR(glm::distance(origin(world[0]), pose.root_translation), 0.0f, 1e-6f);
  for (int j : {2, 3})
    EXPECT_NEAR(glm::distance(origin(world[j]), origin(rest[j]) + glm::vec3(0.5f, 0, -2)), 0.0f,
                1e-5f);
}

TEST(SkinningMatrices, IdentityAtRestAndMoveRestPointsWithTheirJoint) {
  const Skeleton skeleton = two_tree_skeleton();
  const std::vector<glm::mat4> rest_inverse = world_rest_inverse_matrices(skeleton);
  std::vector<glm::mat4> world(skeleton.joints.size()), skinning(skeleton.joints.size());
  forward_kinematics(skeleton, rest_pose(skeleton), world);
  skinning_matrices(world, rest_inverse, skinning);
  // world * inverse(world) in float: round-off of a 4x4 inverse with a scale of 2.
  for (const glm::mat4& s : skinning) EXPECT_LT(max_difference(s, glm::mat4(1.0f)), 1e-5f);

  Pose pose = rest_pose(skeleton);
  pose.local_rotations[1] = glm::angleAxis(1.2f, glm::normalize(glm::vec3(1, 2, 3)));
  pose.root_translation += glm::vec3(0.1f, 0.2f, 0.3f);
  forward_kinematics(skeleton, pose, world);
  skinning_matrices(world, rest_inverse, skinning);
  // The hand joint's rest position, moved by the elbow's skinning matrix, lands on the posed
  // hand joint (the hand is rigidly attached to the elbow). Round-off of a few products.
  const glm::vec3 hand_rest = origin(skeleton.world_rest_matrices()[2]);
  const glm::vec3 moved = glm::vec3(skinning[1] * glm::vec4(hand_rest, 1.0f));
  EXPECT_NEAR(glm::distance(moved, origin(world[2])), 0.0f, 1e-5f);
}

TEST(PoseValidation, RestPoseIsValidAndUnchanged) {
  const Skeleton skeleton = two_tree_skeleton();
  Pose pose = rest_pose(skeleton);
  const Pose before = pose;
  EXPECT_EQ(normalize_and_validate(pose, skeleton), "");
  for (int j = 0; j < skeleton.size(); ++j)
    EXPECT_EQ(pose.local_rotations[j], before.local_rotations[j]) << "joint " << j;
}

TEST(PoseValidation, WrongJointCountIsNamed) {
  const Skeleton skeleton = two_tree_skeleton();
  Pose pose = rest_pose(skeleton);
  pose.local_rotations.pop_back();
  const std::string why = normalize_and_validate(pose, skeleton);
  EXPECT_NE(why.find("3 joint rotations"), std::string::npos) << why;
  EXPECT_NE(why.find("4 joints"), std::string::npos) << why;
}

TEST(PoseValidation, NonFiniteAndZeroRotationsNameTheJoint) {
  const Skeleton skeleton = two_tree_skeleton();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const glm::quat& bad :
       {glm::quat(nan, 0, 0, 0), glm::quat(1, inf, 0, 0), glm::quat(0, 0, 0, 0)}) {
    Pose pose = rest_pose(skeleton);
    pose.local_rotations[2] = bad;
    const std::string why = normalize_and_validate(pose, skeleton);
    EXPECT_NE(why.find("joint 2 ('hand')"), std::string::npos) << why;
  }
  Pose pose = rest_pose(skeleton);
  pose.local_rotations[2] = glm::quat(0, 0, 0, 0);
  EXPECT_NE(normalize_and_validate(pose, skeleton).find("zero-length"), std::string::npos);
  pose = rest_pose(skeleton);
  pose.root_translation.y = nan;
  EXPECT_NE(normalize_and_validate(pose, skeleton).find("root translation"), std::string::npos);
}

TEST(PoseValidation, NonUnitQuaternionsAreNormalisedInPlace) {
  const Skeleton skeleton = two_tree_skeleton();
  Pose pose = rest_pose(skeleton);
  const glm::quat unit = glm::angleAxis(0.7f, glm::normalize(glm::vec3(1, -1, 2)));
  pose.local_rotations[1] = unit * 3.5f;
  pose.local_rotations[3] = unit * 1e-20f;  // tiny but not zero: still a direction
  ASSERT_EQ(normalize_and_validate(pose, skeleton), "");
  // float normalisation: a few ulps.
  for (int j : {1, 3}) {
    EXPECT_NEAR(glm::length(pose.local_rotations[j]), 1.0f, 1e-6f) << "joint " << j;
    EXPECT_NEAR(std::abs(glm::dot(pose.local_rotations[j], unit)), 1.0f, 1e-6f) << "joint " << j;
  }
}

}  // namespace
}  // namespace sweepd::deform::pose_test
