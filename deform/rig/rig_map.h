// RigMap: which joints of a skeleton form the torso, neck, arms and legs — the parts the
// binding covers with sweeps — and which joints start the parts left to skinning (hands,
// feet, head).
//
// detect_rig_map finds the map from the joint names (CMU MotionBuilder and 3ds-Max style,
// Mixamo, Unreal, Blender Rigify, SMPL, VRM humanoid; see rig_naming.h) and, when no naming
// convention fits at all, from the rest-pose geometry (rig_topology.h). A JSON file can
// override it (io/rig_map_json.h).
//
// All joint ids are indices into Skeleton::joints; -1 marks an optional role that is absent.
// Limb chains list only their role joints, root first; in-between joints (twist or segment
// bones) are not listed. Every role is a strict descendant of the one before it.
#pragma once

#include <string>
#include <vector>

#include "deform/model/skeleton.h"

namespace sweepd::deform {

struct ArmJoints {
  int clavicle = -1;  // optional (shoulder blade / collar bone)
  int upper = -1;     // shoulder joint: the upper arm starts here
  int lower = -1;     // elbow: the forearm starts here
  int hand = -1;      // wrist: the hand (skinned part) starts here
  // [clavicle,] upper, lower, hand — root first.
  std::vector<int> chain() const;
};

struct LegJoints {
  int hip = -1;    // optional (CMU's LHipJoint: a pelvis-to-hip link)
  int upper = -1;  // hip joint: the thigh starts here
  int lower = -1;  // knee: the shin starts here
  int foot = -1;   // ankle: the foot (skinned part) starts here
  int toe = -1;    // optional: ball of the foot
  // [hip,] upper, lower, foot[, toe] — root first.
  std::vector<int> chain() const;
};

struct TorsoJoints {
  // Every joint from the pelvis up the spine to the chest (where arms and neck branch off),
  // in hierarchy order, pelvis first; at least two joints.
  std::vector<int> chain;
  int pelvis() const { return chain.empty() ? -1 : chain.front(); }
  int chest() const { return chain.empty() ? -1 : chain.back(); }
};

struct NeckJoints {
  // Every joint from the chest's child up to the head, in hierarchy order; ends with head.
  std::vector<int> chain;
  int head = -1;  // the head (skinned part) starts here
};

struct RigMap {
  std::string convention;  // e.g. "cmu_motionbuilder", "unreal", "topological", "json"
  TorsoJoints torso;
  NeckJoints neck;
  ArmJoints left_arm, right_arm;  // the character's own left/right
  LegJoints left_leg, right_leg;

  // The joints where the skinned (LBS) remainder starts: head, left hand, right hand,
  // left foot, right foot (in this order). Their descendants follow them.
  std::vector<int> skinned_part_roots() const;
};

// Which body part a joint belongs to (see label_joints).
enum class BodyPart {
  kNone,  // above the pelvis (e.g. a root at the floor)
  kTorso,
  kNeck,
  kHead,
  kLeftArm,
  kRightArm,
  kLeftHand,
  kRightHand,
  kLeftLeg,
  kRightLeg,
  kLeftFoot,
  kRightFoot,
};
const char* to_string(BodyPart part);

// Finds the rig map of a skeleton. Throws std::invalid_argument when it cannot, saying which
// part is missing and which joint names were expected, or which chain breaks the hierarchy.
RigMap detect_rig_map(const Skeleton& skeleton);

// Empty when the map fits the skeleton: every id in range, required roles present, each limb
// role a strict descendant of the previous one, the torso a parent-child path (at least two
// joints), the neck a parent-child path from a child of the chest to the head, every limb
// below the pelvis and no joint used twice. Otherwise the first problem, naming the part and
// the joints. (Which side a limb is on is not checked: an override may say anything.)
std::string validate_rig_map(const RigMap& map, const Skeleton& skeleton);

// Per joint (size skeleton.size()): the body part it belongs to. Role joints set the part
// (clavicle/upper/lower: arm, hand: hand, hip/upper/lower: leg, foot: foot, torso chain:
// torso, neck chain: neck, head: head); every other joint takes its parent's part, so
// fingers belong to the hand, toes to the foot and twist bones to their limb.
std::vector<BodyPart> label_joints(const RigMap& map, const Skeleton& skeleton);

// Human-readable listing of the map by joint names, one part per line (for sweepctl).
// `map` must fit `skeleton` (validate_rig_map).
std::string describe(const RigMap& map, const Skeleton& skeleton);

}  // namespace sweepd::deform
