// RigMap: which joints of a skeleton form the torso, neck, arms and legs — the parts the
// binding covers with sweeps — and which joints start the parts left to skinning (hands,
// feet, head).
//
// detect_rig_map finds the map part by part: from the joint names first (the conventions of
// rig_naming.h), then, for every part the names did not settle, from the skeleton's shape
// (rig_topology.h). A part found neither way (no legs, no head) is absent: the binding leaves
// it to the model's own skinning and the map names it in a warning. Only a skeleton with no
// torso chain is refused. A JSON file can override the map (io/json/rig_map_json.h).
//
// All joint ids are indices into Skeleton::joints; -1 marks an optional role that is absent.
// Limb chains list only their role joints, root first; in-between joints (twist or segment
// bones) are not listed. Every role is a strict descendant of the one before it. An absent
// limb has every role -1; an absent head has an empty neck chain and head -1.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "deform/model/skeleton.h"

namespace sweepd::deform {

struct ArmJoints {
  int clavicle = -1;  // optional (shoulder blade / collar bone)
  int upper = -1;     // shoulder joint: the upper arm starts here
  int lower = -1;     // elbow: the forearm starts here
  int hand = -1;      // wrist: the hand (skinned part) starts here; -1 where the forearm's
                      // joint carries the hand (OpenPose): the forearm is then skinned
  // [clavicle,] upper, lower[, hand] — root first.
  std::vector<int> chain() const;
  bool absent() const { return clavicle < 0 && upper < 0 && lower < 0 && hand < 0; }
};

struct LegJoints {
  int hip = -1;    // optional (CMU's LHipJoint: a pelvis-to-hip link)
  int upper = -1;  // hip joint: the thigh starts here
  int lower = -1;  // knee: the shin starts here
  int foot = -1;   // ankle: the foot (skinned part) starts here
  int toe = -1;    // optional: ball of the foot
  // [hip,] upper, lower, foot[, toe] — root first.
  std::vector<int> chain() const;
  bool absent() const { return hip < 0 && upper < 0 && lower < 0 && foot < 0 && toe < 0; }
};

struct TorsoJoints {
  // Every joint from the pelvis up the spine to the chest (where arms and neck branch off),
  // in hierarchy order, pelvis first; one joint where legs, arms and neck all branch off one
  // (a one-joint torso: low-poly game rigs, OpenPose's MidHip).
  std::vector<int> chain;
  int pelvis() const { return chain.empty() ? -1 : chain.front(); }
  int chest() const { return chain.empty() ? -1 : chain.back(); }
};

struct NeckJoints {
  // Every joint from the chest's child up to the head, in hierarchy order; ends with head.
  std::vector<int> chain;
  int head = -1;  // the head (skinned part) starts here
};

// The parts detect_rig_map looks for, in the order of RigMap::found.
enum class RigPart : std::uint8_t { kTorso, kHead, kLeftArm, kRightArm, kLeftLeg, kRightLeg };
inline constexpr int kRigPartCount = 6;
const char* to_string(RigPart part);  // "torso", "head", "left arm", ...

// How a part of the map was found.
enum class PartFinding : std::uint8_t {
  kGiven,    // set by the caller (a JSON override, a map built in code)
  kByName,   // from the joint names
  kByShape,  // from the skeleton's shape (the names did not settle it)
  kAbsent,   // found neither way: left to the model's own skinning
};
const char* to_string(PartFinding finding);  // "given", "by name", "by shape", "absent"

struct PartDetection {
  PartFinding finding = PartFinding::kGiven;
  std::string note;  // why names did not settle it (for kByShape, kAbsent); "" otherwise
};

struct RigMap {
  std::string convention;  // e.g. "cmu_motionbuilder", "unreal", "topological", "json"
  TorsoJoints torso;
  NeckJoints neck;
  ArmJoints left_arm, right_arm;  // the character's own left/right
  LegJoints left_leg, right_leg;
  // How detect_rig_map found each part (index: RigPart), and one warning per absent part
  // ("no legs found: legs are skinned by linear blending (...)"). Not stored in .sweepbind.
  std::array<PartDetection, kRigPartCount> found{};
  std::vector<std::string> warnings;

  bool has_head() const { return neck.head >= 0; }

  // The joints where the skinned (LBS) remainder starts: head, left hand, right hand,
  // left foot, right foot (in this order; -1 for an absent part). Their descendants follow
  // them.
  std::vector<int> skinned_part_roots() const;

  // The joints the torso's sweep follows (deform/binding/bind.cpp): the torso chain, pelvis up to
  // the chest; where that is one joint with a neck above it (OpenPose's MidHip, from which the
  // arms and the head hang), on up to the neck's first joint, where the neck meets the
  // shoulders: the keypoint rigs' one spine bone runs from the mid-hip to the neck. Fewer than
  // two joints: no torso sweep (a lone torso joint is skinned).
  std::vector<int> torso_sweep_chain() const;
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

// Finds the rig map of a skeleton, part by part (names, then shape). Throws
// std::invalid_argument only when it finds no torso chain (pelvis up to the chest), saying
// what the names lacked and where the shape search stopped.
RigMap detect_rig_map(const Skeleton& skeleton);

// Empty when the map fits the skeleton: every id in range, required roles present in every
// limb that is not absent, each limb role a strict descendant of the previous one, the torso a
// parent-child path (at least one joint), the neck (unless the head is absent) a parent-child
// path from a child of the chest to the head, every limb below the pelvis and no joint used
// twice; a limb may also hang from a root of its own beside the pelvis's (a glTF armature
// whose legs are roots, as OpenPose's). Otherwise the first problem, naming the part and the joints. (Which side a limb is on
// is not checked: an override may say anything.)
std::string validate_rig_map(const RigMap& map, const Skeleton& skeleton);

// Per joint (size skeleton.size()): the body part it belongs to. Role joints set the part
// (clavicle/upper/lower: arm, hand: hand, hip/upper/lower: leg, foot: foot, torso chain:
// torso, neck chain: neck, head: head); every other joint takes its parent's part, so
// fingers belong to the hand, toes to the foot and twist bones to their limb.
std::vector<BodyPart> label_joints(const RigMap& map, const Skeleton& skeleton);

// The body's rest-pose axes from the map: up (pelvis to chest) and left, made orthogonal to up.
// Left points from the right upper arm to the left one; without both arms, from the right
// thigh to the left one; without either pair, the glTF convention's left (+X) off up.
// world_rest: the skeleton's world rest matrices (Skeleton::world_rest_matrices).
// The torso's rest up: pelvis to chest; for a one-joint torso from the hips (the legs' upper
// joints) to the shoulders and neck base; +Y when nothing tells.
glm::vec3 rest_torso_up(const RigMap& map, std::span<const glm::mat4> world_rest);

struct BodyAxes {
  glm::vec3 up, left, forward;  // unit; forward = left x up
  const char* left_from = "";   // what told left from right: "the arms", "the thighs", or none
};
BodyAxes rest_body_axes(const RigMap& map, std::span<const glm::mat4> world_rest);

// Human-readable listing of the map by joint names, one part per line, each with how it was
// found, then the warnings (for sweepctl).
// `map` must fit `skeleton` (validate_rig_map).
std::string describe(const RigMap& map, const Skeleton& skeleton);

}  // namespace sweepd::deform
