// named_joints: names of the model's own and of any one rig naming convention find the model's
// joints (by name, then by the role the convention gives); unknown names and two names for one
// joint are refused naming them; the pose keeps unnamed joints at rest.
#include "motion/named_joints.h"

#include <gtest/gtest.h>

namespace sweepd::motion {
namespace {

// Hips - Spine - {LeftArm - LeftForeArm - LeftHand, Head}, with its rig map.
struct SmallRig {
  deform::Skeleton skeleton;
  deform::RigMap rig;
  SmallRig() {
    const glm::quat tilted = glm::angleAxis(0.3f, glm::vec3(0, 0, 1));
    skeleton.joints = {{.name = "Hips"},
                       {.name = "Spine", .parent = 0},
                       {.name = "LeftArm", .parent = 1, .rest_rotation = tilted},
                       {.name = "LeftForeArm", .parent = 2},
                       {.name = "LeftHand", .parent = 3},
                       {.name = "Head", .parent = 1}};
    rig.torso.chain = {0, 1};
    rig.left_arm = {.upper = 2, .lower = 3, .hand = 4};
    rig.neck = {.chain = {5}, .head = 5};
  }
};

std::string refusal(const SmallRig& model, const std::vector<std::string>& names) {
  try {
    named_joints(model.skeleton, model.rig, names);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "(mapped)";
}

TEST(NamedJoints, OwnNamesAndAnotherConventionsNamesFindTheSameJoints) {
  const SmallRig model;
  const std::vector<int> own = {2, 4, 1};
  EXPECT_EQ(named_joints(model.skeleton, model.rig,
                         std::vector<std::string>{"LeftArm", "LeftHand", "Spine"}),
            own);
  EXPECT_EQ(named_joints(model.skeleton, model.rig,
                         std::vector<std::string>{"upperarm_l", "hand_l", "Spine", "head"}),
            (std::vector<int>{2, 4, 1, 5}));
  EXPECT_EQ(named_joints(model.skeleton, model.rig,
                         std::vector<std::string>{"J_Bip_L_UpperArm", "J_Bip_L_LowerArm"}),
            (std::vector<int>{2, 3}));
}

TEST(NamedJoints, UnknownNamesAndOneJointNamedTwiceAreRefusedNamingThem) {
  const SmallRig model;
  const std::string unknown = refusal(model, {"upperarm_l", "tail_01", "thigh_l"});
  EXPECT_NE(unknown.find("unknown joint names 'tail_01', 'thigh_l'"), std::string::npos)
      << unknown;  // the model has no left leg for thigh_l's role
  EXPECT_NE(unknown.find("(unreal)"), std::string::npos) << unknown;
  EXPECT_EQ(refusal(model, {"LeftArm", "upperarm_l", "lowerarm_l"}),
            "'LeftArm' and 'upperarm_l' both name model joint 'LeftArm'");
}

TEST(NamedJoints, UnnamedJointsKeepTheirRestRotation) {
  const SmallRig model;
  const glm::quat bend = glm::angleAxis(0.5f, glm::vec3(1, 0, 0));
  const std::vector<int> joints = {3};
  const deform::Pose pose =
      pose_from_named_rotations(model.skeleton, joints, std::vector<glm::quat>{bend}, {0, 2, 0});
  ASSERT_EQ(pose.local_rotations.size(), 6u);
  EXPECT_EQ(pose.local_rotations[3], bend);
  EXPECT_EQ(pose.local_rotations[2], model.skeleton.joints[2].rest_rotation);
  EXPECT_EQ(pose.root_translation, glm::vec3(0, 2, 0));
}

}  // namespace
}  // namespace sweepd::motion
