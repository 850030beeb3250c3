// RigMap detection on the shared real models: the MakeHuman male by its CMU names, the Khronos
// RiggedFigure (unnamed joints) and the corpus's OpenPose body by the topological fallback.
// Expected chains were read off the files' node hierarchies and joint positions by hand (see
// SOURCES.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "tests/mirrored_model.h"
#include "tests/motion/test_bodies.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> names(const Skeleton& skeleton, const std::vector<int>& chain) {
  std::vector<std::string> result;
  for (int j : chain) result.push_back(j < 0 ? "-" : skeleton.joints[j].name);
  return result;
}

using Names = std::vector<std::string>;

TEST(RigMapSharedModels, MaleIsCmuMotionBuilderWithEveryChain) {
  const fs::path file = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const Skeleton skeleton = io::load_gltf(file).skeleton;
  const RigMap rig = detect_rig_map(skeleton);
  EXPECT_EQ(rig.convention, "cmu_motionbuilder");
  EXPECT_EQ(names(skeleton, rig.torso.chain), (Names{"Hips", "LowerBack", "Spine", "Spine1"}));
  EXPECT_EQ(names(skeleton, rig.neck.chain), (Names{"Neck", "Neck1", "Head"}));
  EXPECT_EQ(names(skeleton, rig.left_arm.chain()),
            (Names{"LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand"}));
  EXPECT_EQ(names(skeleton, rig.right_arm.chain()),
            (Names{"RightShoulder", "RightArm", "RightForeArm", "RightHand"}));
  EXPECT_EQ(names(skeleton, rig.left_leg.chain()),
            (Names{"LHipJoint", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"}));
  EXPECT_EQ(names(skeleton, rig.right_leg.chain()),
            (Names{"RHipJoint", "RightUpLeg", "RightLeg", "RightFoot", "RightToeBase"}));
  EXPECT_EQ(validate_rig_map(rig, skeleton), "");
}

TEST(RigMapSharedModels, RiggedFigureIsFoundByItsShape) {
  const fs::path file = fs::path(SWEEPD_SHARED_DATA) / "models/RiggedFigure/RiggedFigure.gltf";
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const Skeleton skeleton = io::load_gltf(file).skeleton;
  const RigMap rig = detect_rig_map(skeleton);
  EXPECT_EQ(rig.convention, "topological");
  EXPECT_EQ(names(skeleton, rig.torso.chain), (Names{"joint_2", "joint_11", "joint_12"}));
  EXPECT_EQ(names(skeleton, rig.neck.chain), (Names{"joint_19", "joint_20"}));
  EXPECT_EQ(names(skeleton, rig.left_arm.chain()), (Names{"joint_16", "joint_17", "joint_18"}));
  EXPECT_EQ(names(skeleton, rig.right_arm.chain()), (Names{"joint_13", "joint_14", "joint_15"}));
  EXPECT_EQ(names(skeleton, rig.left_leg.chain()),
            (Names{"joint_7", "joint_8", "joint_9", "joint_10"}));
  EXPECT_EQ(names(skeleton, rig.right_leg.chain()),
            (Names{"joint_3", "joint_4", "joint_5", "joint_6"}));
  EXPECT_EQ(validate_rig_map(rig, skeleton), "");
}

// OpenPose (corpus, SOURCES.md): MidHip, LHip and RHip are three roots under the armature node
// (not a joint), at the same point; the neck and both "shoulders" branch from MidHip at the
// neck's base, so the torso is one joint; joints sit at the start of the bone named after the
// keypoint it reaches (LElbow at the shoulder, LWrist at the elbow, no joint at the wrist).
TEST(RigMapSharedModels, OpenPoseBodyWithOneJointTorsoAndRootLegsBinds) {
  const fs::path file =
      fs::path(SWEEPD_SHARED_DATA) / "models/corpus/makehuman_female_slim_openpose.glb";
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const Skeleton skeleton = io::load_gltf(file).skeleton;
  const RigMap rig = detect_rig_map(skeleton);
  EXPECT_EQ(rig.convention, "topological");
  EXPECT_EQ(names(skeleton, rig.torso.chain), (Names{"MidHip"}));
  EXPECT_EQ(names(skeleton, rig.neck.chain), (Names{"Neck"}));
  EXPECT_EQ(names(skeleton, rig.left_arm.chain()), (Names{"LShoulder", "LElbow", "LWrist"}));
  EXPECT_EQ(rig.left_arm.hand, -1) << "no joint at the wrist: LWrist carries forearm and hand";
  EXPECT_EQ(names(skeleton, rig.right_arm.chain()), (Names{"RShoulder", "RElbow", "RWrist"}));
  EXPECT_EQ(names(skeleton, rig.left_leg.chain()),
            (Names{"LHip", "LKnee", "LAnkle", "LBigToe", "LSmallToe"}));
  EXPECT_EQ(names(skeleton, rig.right_leg.chain()),
            (Names{"RHip", "RKnee", "RAnkle", "RBigToe", "RSmallToe"}));
  EXPECT_EQ(validate_rig_map(rig, skeleton), "");
  // What is skinned instead of swept is said, part by part. The torso is not among them: its
  // sweep runs from MidHip up to the neck's first joint, at the neck's base.
  ASSERT_EQ(rig.warnings.size(), 3u);
  EXPECT_NE(rig.warnings[0].find("the neck is one joint ('Neck'"), std::string::npos);
  EXPECT_NE(rig.warnings[1].find("left forearm is skinned"), std::string::npos);
  EXPECT_NE(rig.warnings[2].find("right forearm is skinned"), std::string::npos);
  EXPECT_EQ(names(skeleton, rig.torso_sweep_chain()), (Names{"MidHip", "Neck"}));
}

// The facing is read from the side names (rest_body_axes), so a rig whose Left and Right names
// are exchanged without its geometry would be read facing backwards in silence. Every shared
// body as it is gets no such warning; with only its names swapped (tests/mirrored_model.h's
// side_swapped, the geometry as it was), every body whose sides were read from names is warned
// of, naming the joint; a body sided by its shape (the toes) is read as before.
TEST(RigMapSharedModels, SideNamesThatContradictTheToesAreWarnedOf) {
  int warned = 0;
  for (const test_models::Body& body : test_models::every_body()) {
    std::optional<Model> model = test_models::load_body(body);
    if (!model) continue;
    const auto contradiction = [](const RigMap& rig) {
      return std::count_if(rig.warnings.begin(), rig.warnings.end(), [](const std::string& w) {
        return w.find("the side names contradict the feet") != std::string::npos;
      });
    };
    const RigMap rig = detect_rig_map(model->skeleton);
    EXPECT_EQ(contradiction(rig), 0) << body.file;
    Skeleton swapped = model->skeleton;
    for (Joint& joint : swapped.joints) joint.name = test_models::side_swapped(joint.name);
    const RigMap swapped_rig = detect_rig_map(swapped);
    const bool named_sides =
        rig.found[static_cast<int>(RigPart::kLeftArm)].finding == PartFinding::kByName ||
        rig.found[static_cast<int>(RigPart::kLeftLeg)].finding == PartFinding::kByName;
    EXPECT_EQ(contradiction(swapped_rig), named_sides ? 1 : 0) << body.file;
    if (named_sides) {
      warned++;
      const std::string left = swapped.joints[swapped_rig.left_leg.upper].name;
      EXPECT_NE(std::find_if(swapped_rig.warnings.begin(), swapped_rig.warnings.end(),
                             [&](const std::string& w) {
                               return w.find("'" + left + "'") != std::string::npos;
                             }),
                swapped_rig.warnings.end())
          << body.file << ": the warning names the joint read as the left thigh";
    }
  }
  // The male (CMU names), the three Mixamo/Unreal corpus bodies and the mannequin (made here,
  // never absent) name their sides; the RiggedFigure and the OpenPose body are sided by shape.
  const bool shared = fs::exists(fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb");
  EXPECT_EQ(warned, shared ? 5 : 1);
}

}  // namespace
}  // namespace sweepd::deform
