// The VMC stream's messages (server/services/vmc/vmc_stream.h): bones land on the model's joints
// mirrored from Unity's frame into glTF's; what a frame is; wrongly typed messages and unknown
// bone names dropped and counted, other addresses ignored and counted, neither moving a joint.
#include "server/services/vmc/vmc_stream.h"

#include <gtest/gtest.h>

#include <limits>

#include "deform/rig/rig_map.h"
#include "server/services/vmc/unity_frame.h"
#include "tests/server/services/vmc/vmc_packets.h"

namespace sweepd::server {
namespace {

using test::VmcBone;

// How far apart two rotations' quaternions are (component-wise).
float apart(glm::quat a, glm::quat b) {
  return glm::length(glm::vec4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w));
}

// A small humanoid: hips, spine, chest, neck, head, and per side an arm and a leg.
deform::Skeleton humanoid() {
  deform::Skeleton skeleton;
  const auto add = [&](const char* name, int parent, glm::vec3 at) {
    deform::Joint joint;
    joint.name = name;
    joint.parent = parent;
    joint.rest_translation = at;
    skeleton.joints.push_back(joint);
    return skeleton.size() - 1;
  };
  const int hips = add("Hips", -1, {0, 1, 0});
  const int spine = add("Spine", hips, {0, 0.1f, 0});
  const int chest = add("Chest", spine, {0, 0.2f, 0});
  const int neck = add("Neck", chest, {0, 0.2f, 0});
  add("Head", neck, {0, 0.1f, 0});
  for (const float side : {1.0f, -1.0f}) {
    const bool left = side > 0;
    const int upper = add(left ? "LeftUpperArm" : "RightUpperArm", chest, {side * 0.2f, 0.15f, 0});
    const int lower = add(left ? "LeftLowerArm" : "RightLowerArm", upper, {side * 0.3f, 0, 0});
    add(left ? "LeftHand" : "RightHand", lower, {side * 0.25f, 0, 0});
    const int thigh = add(left ? "LeftUpperLeg" : "RightUpperLeg", hips, {side * 0.1f, -0.05f, 0});
    const int shin = add(left ? "LeftLowerLeg" : "RightLowerLeg", thigh, {0, -0.45f, 0});
    add(left ? "LeftFoot" : "RightFoot", shin, {0, -0.45f, 0});
  }
  return skeleton;
}

class VmcStreamTest : public ::testing::Test {
 protected:
  void SetUp() override {
    rig_ = deform::detect_rig_map(skeleton_);
    bones_ = deform::map_human_body_bones(skeleton_, rig_);
  }
  // Applies the packet of `bytes`; whether it ended a frame.
  bool apply(std::vector<std::byte> bytes) {
    const auto packet = read_osc_packet(bytes);
    EXPECT_TRUE(packet);
    return stream_.apply(*packet, counters_);
  }
  bool apply_message(lo_message message, const char* address) {
    return apply(test::osc_bytes(message, address));
  }
  deform::Pose pose() const { return stream_.pose_for(skeleton_, bones_); }
  int joint(const std::string& name) const {
    for (int j = 0; j < skeleton_.size(); ++j)
      if (skeleton_.joints[j].name == name) return j;
    return -1;
  }

  deform::Skeleton skeleton_ = humanoid();
  deform::RigMap rig_;
  std::array<int, deform::kHumanBodyBoneCount> bones_{};
  VmcStream stream_;
  VmcCounters counters_;
};

TEST_F(VmcStreamTest, ABundleOfBonesPosesTheirJointsMirroredFromUnitysFrame) {
  // 30° about Unity's (1, 2, 3) axis: glTF's rotation is about (1, -2, -3) by the same angle.
  const glm::quat unity = glm::angleAxis(glm::radians(30.0f), glm::normalize(glm::vec3(1, 2, 3)));
  lo_bundle frame = test::vmc_frame_bundle(
      {{"LeftUpperArm", {0.2f, 0.15f, 0}, unity}, {"Hips", {0.5f, 0.9f, -0.25f}, unity}}, 0.1f);
  const bool ended = apply(test::bundle_bytes(frame));
  lo_bundle_free_recursive(frame);
  EXPECT_TRUE(ended);
  const deform::Pose posed = pose();
  const glm::quat expected =
      glm::angleAxis(glm::radians(30.0f), glm::normalize(glm::vec3(1, -2, -3)));
  EXPECT_LT(apart(posed.local_rotations[joint("LeftUpperArm")], expected), 1e-6f);
  EXPECT_LT(apart(posed.local_rotations[0], expected), 1e-6f);
  // The hips' position is the root translation, x mirrored; the arm's position is not used.
  EXPECT_EQ(posed.root_translation, glm::vec3(-0.5f, 0.9f, -0.25f));
  const deform::Pose rest = deform::rest_pose(skeleton_);
  for (int j = 0; j < skeleton_.size(); ++j) {
    if (j == 0 || j == joint("LeftUpperArm")) continue;
    EXPECT_EQ(posed.local_rotations[j], rest.local_rotations[j]) << skeleton_.joints[j].name;
  }
  EXPECT_EQ(counters_.bundles, 1u);
  EXPECT_EQ(counters_.messages, 4u);
  EXPECT_EQ(counters_.bones, 2u);
  EXPECT_EQ(counters_.dropped_messages + counters_.ignored_messages, 0u);
}

TEST_F(VmcStreamTest, TheMirrorIsItsOwnInverse) {
  const glm::quat q = glm::normalize(glm::quat(0.3f, -0.4f, 0.5f, 0.7f));
  EXPECT_EQ(unity_mirrored(unity_mirrored(q)), q);
  EXPECT_EQ(unity_mirrored(unity_mirrored(glm::vec3(1, 2, 3))), glm::vec3(1, 2, 3));
  // A rotation of the mirrored frame, applied to a mirrored vector, is the mirror of the original.
  const glm::vec3 v(0.3f, -1.2f, 2.0f);
  const glm::vec3 turned = unity_mirrored(q * v);
  EXPECT_LT(glm::length(unity_mirrored(q) * unity_mirrored(v) - turned), 1e-6f);
}

TEST_F(VmcStreamTest, LoneMessagesEndAFrameOnlyWithOkOrTime) {
  EXPECT_FALSE(apply_message(test::vmc_bone_message({"Head"}), "/VMC/Ext/Bone/Pos"));
  lo_message time = lo_message_new();
  lo_message_add_float(time, 2.0f);
  EXPECT_TRUE(apply_message(time, "/VMC/Ext/T"));
  lo_message ok = lo_message_new();
  for (int value : {1, 3, 1}) lo_message_add_int32(ok, value);  // loaded, calibration state, mode
  EXPECT_TRUE(apply_message(ok, "/VMC/Ext/OK"));
  EXPECT_EQ(counters_.dropped_messages, 0u);
}

TEST_F(VmcStreamTest, WrongTypesUnknownBonesAndOtherAddressesMoveNothing) {
  lo_message ints = lo_message_new();
  lo_message_add_string(ints, "Head");
  for (int i = 0; i < 7; ++i) lo_message_add_int32(ints, 1);
  EXPECT_FALSE(apply_message(ints, "/VMC/Ext/Bone/Pos"));
  lo_message short_bone = lo_message_new();
  lo_message_add_string(short_bone, "Head");
  lo_message_add_float(short_bone, 0.0f);
  EXPECT_FALSE(apply_message(short_bone, "/VMC/Ext/Bone/Pos"));
  EXPECT_FALSE(apply_message(test::vmc_bone_message({"head", {}, {0.0f, 1.0f, 0.0f, 0.0f}}),
                             "/VMC/Ext/Bone/Pos"))
      << "Unity's names are spelt exactly";
  EXPECT_FALSE(apply_message(test::vmc_bone_message({"Head", {}, {0.0f, 0.0f, 0.0f, 0.0f}}),
                             "/VMC/Ext/Bone/Pos"))
      << "a zero rotation";
  lo_message string_time = lo_message_new();
  lo_message_add_string(string_time, "now");
  EXPECT_FALSE(apply_message(string_time, "/VMC/Ext/T")) << "a T that is not a float ends nothing";
  lo_message blend = lo_message_new();
  lo_message_add_string(blend, "Joy");
  lo_message_add_float(blend, 1.0f);
  EXPECT_FALSE(apply_message(blend, "/VMC/Ext/Blend/Val"));
  EXPECT_EQ(counters_.dropped_messages, 5u);
  EXPECT_EQ(counters_.ignored_messages, 1u);
  EXPECT_EQ(counters_.bones, 0u);
  EXPECT_EQ(pose().local_rotations, deform::rest_pose(skeleton_).local_rotations);
}

TEST_F(VmcStreamTest, TheRootTransformMovesAndTurnsTheWholeBody) {
  const glm::quat turn = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  lo_message root = test::vmc_bone_message({"root", {1.0f, 0.0f, 2.0f}, turn});
  EXPECT_FALSE(apply_message(root, "/VMC/Ext/Root/Pos"));
  const deform::Pose posed = pose();
  // Unity's 90° about +Y is glTF's -90° about +Y; the hips' rest (0, 1, 0) stays on the axis.
  const glm::quat expected = glm::angleAxis(glm::radians(-90.0f), glm::vec3(0, 1, 0));
  EXPECT_LT(apart(posed.local_rotations[0], expected), 1e-6f);
  EXPECT_LT(glm::length(posed.root_translation - glm::vec3(-1.0f, 1.0f, 2.0f)), 1e-6f);
}

// A Root/Pos dropped for its zero rotation (or a value that is not finite) leaves the root as
// it was: before, its position was taken and the zero rotation kept, and every later frame was
// an invalid pose (found by the browser viewer's test, whose sender made that mistake).
TEST_F(VmcStreamTest, ADroppedRootTransformLeavesTheRootAsItWas) {
  const glm::quat turn = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  apply_message(test::vmc_bone_message({"root", {1.0f, 0.0f, 2.0f}, turn}), "/VMC/Ext/Root/Pos");
  const deform::Pose before = pose();
  apply_message(test::vmc_bone_message({"root", {5.0f, 0.0f, 0.0f}, glm::quat(0, 0, 0, 0)}),
                "/VMC/Ext/Root/Pos");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  apply_message(test::vmc_bone_message({"root", {5.0f, 0.0f, 0.0f}, glm::quat(nan, 0, 0, 0)}),
                "/VMC/Ext/Root/Pos");
  EXPECT_EQ(counters_.dropped_messages, 2u);
  const deform::Pose after = pose();
  EXPECT_EQ(after.local_rotations, before.local_rotations);
  EXPECT_EQ(after.root_translation, before.root_translation);
}

}  // namespace
}  // namespace sweepd::server
