#include "deform/rig/human_body_bones.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <tuple>

namespace sweepd::deform {

const std::array<std::string_view, kHumanBodyBoneCount> kHumanBodyBones = {
    "Hips", "LeftUpperLeg", "RightUpperLeg", "LeftLowerLeg", "RightLowerLeg", "LeftFoot",
    "RightFoot", "Spine", "Chest", "Neck", "Head", "LeftShoulder", "RightShoulder",
    "LeftUpperArm", "RightUpperArm", "LeftLowerArm", "RightLowerArm", "LeftHand", "RightHand",
    "LeftToes", "RightToes", "LeftEye", "RightEye", "Jaw",
    "LeftThumbProximal", "LeftThumbIntermediate", "LeftThumbDistal",
    "LeftIndexProximal", "LeftIndexIntermediate", "LeftIndexDistal",
    "LeftMiddleProximal", "LeftMiddleIntermediate", "LeftMiddleDistal",
    "LeftRingProximal", "LeftRingIntermediate", "LeftRingDistal",
    "LeftLittleProximal", "LeftLittleIntermediate", "LeftLittleDistal",
    "RightThumbProximal", "RightThumbIntermediate", "RightThumbDistal",
    "RightIndexProximal", "RightIndexIntermediate", "RightIndexDistal",
    "RightMiddleProximal", "RightMiddleIntermediate", "RightMiddleDistal",
    "RightRingProximal", "RightRingIntermediate", "RightRingDistal",
    "RightLittleProximal", "RightLittleIntermediate", "RightLittleDistal",
    "UpperChest"};

namespace {

// A joint name as compared with a bone's: no namespace ("mixamorig:", "Armature|"), lower case.
std::string comparable(std::string_view name) {
  const std::size_t cut = name.find_last_of(":|");
  if (cut != std::string_view::npos) name.remove_prefix(cut + 1);
  std::string lower(name);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

}  // namespace

int human_body_bone_index(std::string_view name) {
  const auto found = std::find(kHumanBodyBones.begin(), kHumanBodyBones.end(), name);
  return found == kHumanBodyBones.end() ? -1 : static_cast<int>(found - kHumanBodyBones.begin());
}

std::array<int, kHumanBodyBoneCount> map_human_body_bones(const Skeleton& skeleton,
                                                          const RigMap& map) {
  std::array<int, kHumanBodyBoneCount> bones;
  bones.fill(-1);
  std::vector<bool> taken(skeleton.joints.size(), false);
  const auto drive = [&](std::string_view bone, int joint) {
    const int index = human_body_bone_index(bone);
    if (joint < 0 || taken[joint] || bones[index] >= 0) return;
    bones[index] = joint;
    taken[joint] = true;
  };

  drive("Hips", map.torso.pelvis());
  const std::vector<int>& torso = map.torso.chain;
  const std::string_view spine[] = {"Spine", "Chest", "UpperChest"};
  for (std::size_t i = 0; i < 3 && i + 1 < torso.size(); ++i) drive(spine[i], torso[i + 1]);
  if (map.neck.chain.size() >= 2) drive("Neck", map.neck.chain.front());
  drive("Head", map.neck.head);
  for (const auto& [side, arm, leg] :
       {std::tuple{std::string("Left"), &map.left_arm, &map.left_leg},
        std::tuple{std::string("Right"), &map.right_arm, &map.right_leg}}) {
    drive(side + "Shoulder", arm->clavicle);
    drive(side + "UpperArm", arm->upper);
    drive(side + "LowerArm", arm->lower);
    drive(side + "Hand", arm->hand);
    drive(side + "UpperLeg", leg->upper);
    drive(side + "LowerLeg", leg->lower);
    drive(side + "Foot", leg->foot);
    drive(side + "Toes", leg->toe);
  }

  for (int joint = 0; joint < skeleton.size(); ++joint) {
    const std::string name = comparable(skeleton.joints[joint].name);
    for (int bone = 0; bone < kHumanBodyBoneCount; ++bone) {
      if (name == comparable(kHumanBodyBones[bone])) drive(kHumanBodyBones[bone], joint);
    }
  }
  return bones;
}

std::vector<int> joints_without_human_body_bone(
    const Skeleton& skeleton, const std::array<int, kHumanBodyBoneCount>& bones) {
  std::vector<bool> reached(skeleton.joints.size(), false);
  for (int joint : bones) {
    if (joint >= 0) reached[joint] = true;
  }
  std::vector<int> left;
  for (int joint = 0; joint < skeleton.size(); ++joint) {
    if (!reached[joint]) left.push_back(joint);
  }
  return left;
}

}  // namespace sweepd::deform
