// HumanBodyBones (Unity's humanoid bone names, VMC's) onto the corpus's rigs: the body's bones by
// the rig map's roles, whatever the rig's own names (CMU, Mixamo, Unreal); fingers by Unity's or
// VRM's names only; no joint driven twice; what no bone reaches listed.
#include "deform/rig/human_body_bones.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "deform/rig/rig_naming.h"
#include "io/gltf/gltf_load.h"
#include "tests/test_paths.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

// Per bone name, the joint name it drives on the model in `file` (bones driving nothing left
// out), and the joints no bone reaches.
struct BoneNames {
  std::map<std::string, std::string> driven;
  std::vector<std::string> at_rest;
};

BoneNames bone_names(const Skeleton& skeleton) {
  const auto bones = map_human_body_bones(skeleton, detect_rig_map(skeleton));
  BoneNames names;
  for (int bone = 0; bone < kHumanBodyBoneCount; ++bone)
    if (bones[bone] >= 0)
      names.driven[std::string(kHumanBodyBones[bone])] = skeleton.joints[bones[bone]].name;
  for (int joint : joints_without_human_body_bone(skeleton, bones))
    names.at_rest.push_back(skeleton.joints[joint].name);
  return names;
}

Skeleton skeleton_of(const std::string& model) {
  const fs::path file = fs::path(SWEEPD_SHARED_DATA) / "models" / model;
  if (!fs::exists(file)) return {};
  return io::load_gltf(file).skeleton;
}

TEST(HumanBodyBones, UnitysOrderAndNamesAreKnown) {
  EXPECT_EQ(kHumanBodyBones[0], "Hips");
  EXPECT_EQ(kHumanBodyBones[23], "Jaw");
  EXPECT_EQ(kHumanBodyBones[54], "UpperChest");
  EXPECT_EQ(human_body_bone_index("LeftLittleDistal"), 38);
  EXPECT_EQ(human_body_bone_index("leftUpperArm"), -1) << "VMC sends Unity's spelling exactly";
  EXPECT_EQ(human_body_bone_index("LastBone"), -1);
}

TEST(HumanBodyBones, TheSharedMalesCmuRigIsReachedByRoles) {
  const Skeleton skeleton = skeleton_of("makehuman_male_cmu.glb");
  if (skeleton.joints.empty()) GTEST_SKIP() << "no shared data";
  const BoneNames names = bone_names(skeleton);
  const std::map<std::string, std::string> expected = {
      {"Hips", "Hips"},           {"Spine", "LowerBack"},         {"Chest", "Spine"},
      {"UpperChest", "Spine1"},   {"Neck", "Neck"},               {"Head", "Head"},
      {"LeftShoulder", "LeftShoulder"}, {"LeftUpperArm", "LeftArm"},
      {"LeftLowerArm", "LeftForeArm"},  {"LeftHand", "LeftHand"},
      {"LeftUpperLeg", "LeftUpLeg"},    {"LeftLowerLeg", "LeftLeg"},
      {"LeftFoot", "LeftFoot"},         {"LeftToes", "LeftToeBase"},
      {"RightShoulder", "RightShoulder"}, {"RightUpperArm", "RightArm"},
      {"RightLowerArm", "RightForeArm"},  {"RightHand", "RightHand"},
      {"RightUpperLeg", "RightUpLeg"},    {"RightLowerLeg", "RightLeg"},
      {"RightFoot", "RightFoot"},         {"RightToes", "RightToeBase"}};
  EXPECT_EQ(names.driven, expected);
  // CMU's second neck joint, its hip links and its fingers have no HumanBodyBones name.
  std::vector<std::string> at_rest = names.at_rest;
  std::ranges::sort(at_rest);
  EXPECT_EQ(at_rest, (std::vector<std::string>{"LHipJoint", "LThumb", "LeftFingerBase",
                                               "LeftHandFinger1", "Neck1", "RHipJoint", "RThumb",
                                               "RightFingerBase", "RightHandFinger1"}));
}

TEST(HumanBodyBones, AMixamoBodyIsReachedWholeButItsFingers) {
  const Skeleton skeleton = skeleton_of("corpus/makehuman_female_old_heavy_mixamo.glb");
  if (skeleton.joints.empty()) GTEST_SKIP() << "no shared data";
  const BoneNames names = bone_names(skeleton);
  EXPECT_EQ(names.driven.at("Spine"), "mixamorig:Spine");
  EXPECT_EQ(names.driven.at("Chest"), "mixamorig:Spine1");
  EXPECT_EQ(names.driven.at("UpperChest"), "mixamorig:Spine2");
  EXPECT_EQ(names.driven.at("Neck"), "mixamorig:Neck");
  EXPECT_EQ(names.driven.at("LeftToes"), "mixamorig:LeftToeBase");
  EXPECT_EQ(names.driven.size(), 22u) << "every body bone: 6 of the trunk, 8 per side";
  EXPECT_EQ(names.at_rest.size(), 30u) << "Mixamo's 15 finger joints a hand";
  for (const std::string& joint : names.at_rest)
    EXPECT_NE(joint.find("Hand"), std::string::npos) << joint << " is not a finger";
}

TEST(HumanBodyBones, UnitysAndVrmsFingerNamesAreReachedByName) {
  Skeleton skeleton = skeleton_of("makehuman_male_cmu.glb");
  if (skeleton.joints.empty()) GTEST_SKIP() << "no shared data";
  for (Joint& joint : skeleton.joints) {
    if (joint.name == "LeftHandFinger1") joint.name = "Armature|LeftIndexProximal";
    if (joint.name == "RThumb") joint.name = "rightThumbProximal";  // VRM's spelling
  }
  const BoneNames names = bone_names(skeleton);
  EXPECT_EQ(names.driven.at("LeftIndexProximal"), "Armature|LeftIndexProximal");
  EXPECT_EQ(names.driven.at("RightThumbProximal"), "rightThumbProximal");
  EXPECT_EQ(names.at_rest.size(), 7u);
}

TEST(HumanBodyBones, AJointNamedAsABoneTheRolesGaveIsNotDrivenTwice) {
  // The male's "Spine" joint is Unity's Chest by its place in the torso; the name does not drive
  // it a second time, and the bone called Spine stays on LowerBack.
  const Skeleton skeleton = skeleton_of("makehuman_male_cmu.glb");
  if (skeleton.joints.empty()) GTEST_SKIP() << "no shared data";
  const auto bones = map_human_body_bones(skeleton, detect_rig_map(skeleton));
  std::map<int, int> drives;
  for (int joint : bones)
    if (joint >= 0) ++drives[joint];
  for (const auto& [joint, count] : drives) EXPECT_EQ(count, 1) << skeleton.joints[joint].name;
}

// The class, not one file: on every body of the shared data (the corpus, the shared male, the
// RiggedFigure) each joint with a role in its rig map is reached by a bone, but hip links (no
// HumanBodyBones bone is one), and each torso joint up to UpperChest's.
TEST(HumanBodyBones, EveryRoleOfEveryShippedBodyIsReached) {
  std::vector<fs::path> bodies = {"makehuman_male_cmu.glb", "RiggedFigure/RiggedFigure.gltf"};
  const fs::path corpus = fs::path(SWEEPD_SHARED_DATA) / "models/corpus";
  if (!fs::exists(corpus)) GTEST_SKIP() << "no shared data";
  for (const auto& entry : fs::directory_iterator(corpus))
    bodies.push_back(fs::relative(entry.path(), corpus.parent_path()));
  for (const fs::path& body : bodies) {
    const Skeleton skeleton = skeleton_of(body.string());
    ASSERT_FALSE(skeleton.joints.empty()) << body;
    const RigMap map = detect_rig_map(skeleton);
    const auto bones = map_human_body_bones(skeleton, map);
    const std::vector<int> at_rest = joints_without_human_body_bone(skeleton, bones);
    const auto reached = [&](int joint) { return std::ranges::find(at_rest, joint) == at_rest.end(); };
    const std::array<int, kRigRoleCount> roles = rig_roles(map);
    for (int role = 0; role < kRigRoleCount; ++role) {
      const bool hip_link = role == 6 || role == 15;  // rig_roles' order: leg.hip per side
      if (roles[role] < 0 || hip_link) continue;
      EXPECT_TRUE(reached(roles[role])) << body << ": " << skeleton.joints[roles[role]].name;
    }
    for (std::size_t i = 0; i < map.torso.chain.size() && i < 4; ++i)
      EXPECT_TRUE(reached(map.torso.chain[i])) << body << ": " << skeleton.joints[map.torso.chain[i]].name;
    std::string names;
    for (int joint : at_rest) names += " " + skeleton.joints[joint].name;
    std::printf("%s: %zu of %d joints reached; at rest:%s\n", body.string().c_str(),
                skeleton.joints.size() - at_rest.size(), skeleton.size(), names.c_str());
  }
}

}  // namespace
}  // namespace sweepd::deform
