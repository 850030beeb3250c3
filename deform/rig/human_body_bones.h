// HumanBodyBones: Unity's humanoid bone names (UnityEngine.HumanBodyBones, 55 bones), the names
// a VMC stream poses bones by (server/vmc/), as one more rig convention onto a model's RigMap.
//
// map_human_body_bones(skeleton, map) gives, per bone in kHumanBodyBones' order, the model
// joint it drives, or -1:
//   1. by role, from the rig map (rig_map.h): Hips the pelvis; Spine, Chest and UpperChest the
//      torso chain's joints after the pelvis, in order, as far as the chain goes; Neck the neck
//      chain's first joint when the chain has one below the head; Head the head; per side
//      Shoulder, UpperArm, LowerArm, Hand the arm's clavicle, upper, lower, hand, and
//      UpperLeg, LowerLeg, Foot, Toes the leg's upper, lower, foot, toe.
//   2. by name, for the bones left (fingers, eyes, jaw) and any role the map lacks: the model
//      joint whose name, without a namespace up to the last ':' or '|', is the bone's name in
//      any case (HumanBodyBones' "LeftIndexProximal", VRM's "leftIndexProximal").
// No joint is driven by two bones. A model joint no bone reaches keeps its rest rotation
// (CMU's Neck1 and hip links, Mixamo's fingers: their names are not Unity's).
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform {

inline constexpr int kHumanBodyBoneCount = 55;
// In UnityEngine.HumanBodyBones' order (Hips = 0 ... UpperChest = 54).
extern const std::array<std::string_view, kHumanBodyBoneCount> kHumanBodyBones;

// The bone's index in kHumanBodyBones, exact spelling (as VMC sends it); -1 for another name.
int human_body_bone_index(std::string_view name);

// Per bone, the model joint it drives or -1 (see the header). `map` must fit `skeleton`.
std::array<int, kHumanBodyBoneCount> map_human_body_bones(const Skeleton& skeleton,
                                                          const RigMap& map);

// The model joints no bone reaches, in joint order.
std::vector<int> joints_without_human_body_bone(
    const Skeleton& skeleton, const std::array<int, kHumanBodyBoneCount>& bones);

}  // namespace sweepd::deform
