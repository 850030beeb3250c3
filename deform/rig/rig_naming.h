// Rig naming: finds a RigMap from joint names, trying the common naming conventions of
// humanoid rigs in turn.
//
// Conventions (the "convention" string it reports, and the left-arm/left-leg names it looks for;
// right sides alike; matching ignores case, a namespace prefix up to the last ':' or '|',
// and Blender's "DEF-" prefix):
//   cmu_motionbuilder  Hips .. Head;  [LeftShoulder] LeftArm LeftForeArm LeftHand;
//                      [LHipJoint] LeftUpLeg LeftLeg LeftFoot [LeftToeBase]
//   mixamo             the same names behind a "mixamorig:" prefix
//   cmu_3dsmax         Hips .. Head;  [LeftCollar] LeftShoulder LeftElbow LeftWrist;
//                      LeftHip LeftKnee LeftAnkle [LeftToe]
//   unreal             pelvis .. head;  [clavicle_l] upperarm_l lowerarm_l hand_l;
//                      thigh_l calf_l foot_l [ball_l]
//   rigify             [DEF-]spine .. spine.006;  [shoulder.L] upper_arm.L forearm.L hand.L;
//                      thigh.L shin.L foot.L [toe.L]
//   smpl               Pelvis .. Head;  [L_Collar] L_Shoulder L_Elbow L_Wrist;
//                      L_Hip L_Knee L_Ankle [L_Foot]   (SMPL-X's left_shoulder etc. too)
//   vrm                hips .. head;  [leftShoulder] leftUpperArm leftLowerArm leftHand;
//                      leftUpperLeg leftLowerLeg leftFoot [leftToes]
// Only the pelvis, the head and the limb roles are looked up by name. The torso is the
// hierarchy path from the pelvis to the chest (the deepest common ancestor of both arms and
// the head) and the neck the path from there to the head, so any number of spine and neck
// joints fits.
#pragma once

#include <optional>
#include <string>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform {

struct NamedRigMatch {
  // Set when a convention names every part and its chains follow the hierarchy.
  std::optional<RigMap> map;
  // True when, without a map, some convention still names at least one whole limb: the
  // skeleton is named, only incompletely or inconsistently, and a geometric guess would hide
  // the problem.
  bool looks_named = false;
  // Without a map: why not, naming the missing parts and the joint names expected for them.
  std::string problem;
};

NamedRigMatch match_rig_naming(const Skeleton& skeleton);

}  // namespace sweepd::deform
