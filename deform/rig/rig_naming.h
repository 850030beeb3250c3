// Rig naming: which joints the names of a humanoid rig give for each part, trying the common
// naming conventions in turn and keeping the one that names the most parts.
//
// Conventions (the "convention" string it reports, and the left-arm/left-leg names it looks for;
// right sides alike):
//   mixamo             mixamorig[N]:Hips .. Head; [LeftShoulder] LeftArm LeftForeArm LeftHand;
//                      LeftUpLeg LeftLeg LeftFoot [LeftToeBase]   (any "mixamorig" prefix)
//   cmu_motionbuilder  Hips .. Head;  [LeftShoulder] LeftArm LeftForeArm LeftHand;
//                      [LHipJoint] LeftUpLeg LeftLeg LeftFoot [LeftToeBase]
//   cmu_3dsmax         Hips .. Head;  [LeftCollar] LeftShoulder LeftElbow LeftWrist;
//                      LeftHip LeftKnee LeftAnkle [LeftToe]
//   biped              Bip001 Pelvis .. Bip001 Head;  [Bip001 L Clavicle] Bip001 L UpperArm
//                      Bip001 L Forearm Bip001 L Hand;  Bip001 L Thigh Bip001 L Calf
//                      Bip001 L Foot [Bip001 L Toe0]   (3ds Max Biped, any "Bip<digits> ")
//   unreal             pelvis .. head;  [clavicle_l] upperarm_l lowerarm_l hand_l;
//                      thigh_l calf_l foot_l [ball_l]
//   rigify             spine .. spine.006;  [shoulder.L] upper_arm.L forearm.L hand.L;
//                      thigh.L shin.L foot.L [toe.L]   (the metarig, and its DEF-/ORG-/MCH-
//                      layers: a DEF- deform bone wins over the others of the same name)
//   smpl               Pelvis .. Head;  [L_Collar] L_Shoulder L_Elbow L_Wrist;
//                      L_Hip L_Knee L_Ankle [L_Foot]   (SMPL-X's left_shoulder etc. too)
//   vrm                hips .. head;  [leftShoulder] leftUpperArm leftLowerArm leftHand;
//                      leftUpperLeg leftLowerLeg leftFoot [leftToes]; and VRoid's node names
//                      J_Bip_C_Hips .. J_Bip_C_Head, J_Bip_L_UpperArm ...
//   daz_genesis        hip .. head;  [lCollar] lShldrBend lForearmBend lHand;
//                      lThighBend lShin lFoot [lToe]   (Genesis 1-2's lShldr, lForeArm, lThigh)
//   makehuman          root .. head;  [clavicle.L] upperarm01.L lowerarm01.L wrist.L;
//                      [pelvis.L] upperleg01.L lowerleg01.L foot.L [toe1-1.L]
// Matching ignores case, a namespace up to the last ':' or '|' ("ns:name", "Armature|name"),
// Blender's layer prefixes DEF-/ORG-/MCH-, and, where no joint has the exact name, a numbered
// or "_end" suffix (".001", "_end").
//
// Matching is per part: a limb is named when its upper, lower and end roles are all found and
// follow the hierarchy (optional roles that break it are dropped); the torso when the pelvis
// is found, the head when the head is. An optional hip link or clavicle the convention does
// not name is taken from the hierarchy: the upper joint's parent, when only this limb hangs
// below it. The torso and neck chains are not filled here (rig_detection: detect_rig_map).
#pragma once

#include <array>
#include <span>
#include <string>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform {

struct NamedRigParts {
  std::string convention;  // the convention naming the most parts; "" when it names none
  int pelvis = -1;
  // The named parts' roles: neck.head and the limbs, -1 where a part is not named. No torso
  // or neck chain.
  RigMap map;
  // Per part (index RigPart): "" when named, else why not, naming the joints expected.
  std::array<std::string, kRigPartCount> problem;
  bool settles_every_part() const;
};

NamedRigParts match_rig_naming(const Skeleton& skeleton);

// The joint roles a rig map gives, in one fixed order (pelvis, head, then per side the arm's
// clavicle, upper, lower, hand and the leg's hip, upper, lower, foot, toe): -1 where absent.
// Two maps over different skeletons pair their joints role by role through it.
inline constexpr int kRigRoleCount = 20;
std::array<int, kRigRoleCount> rig_roles(const RigMap& map);

// Joint names on their own, without a hierarchy (e.g. a pose keyed by joint name): the roles
// the convention recognising the most of them gives, as indices into `names` in rig_roles'
// order (-1 where no name has that role), matched as match_rig_naming matches (case, namespaces,
// prefixes and suffixes ignored). convention is "" when no name is recognised.
struct NameRoles {
  std::string convention;
  std::array<int, kRigRoleCount> roles;
};
NameRoles match_name_roles(std::span<const std::string> names);

}  // namespace sweepd::deform
