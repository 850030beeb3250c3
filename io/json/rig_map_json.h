// RigMap JSON: the file a user writes to override the detected rig map (deform/rig/rig_map.h),
// and writes out to start from the detected one. Joints are named, never numbered.
//
// Format (every part required; limbs list their roles by key, optional roles may be left out):
//   {
//     "convention": "cmu_motionbuilder",                    // optional, for people only
//     "torso": ["Hips", "LowerBack", "Spine", "Spine1"],    // pelvis .. chest, parent to child
//     "neck": ["Neck", "Neck1", "Head"],                    // child of the chest .. head
//     "left_arm": {"clavicle": "LeftShoulder", "upper": "LeftArm",
//                  "lower": "LeftForeArm", "hand": "LeftHand"},        // clavicle optional
//     "right_arm": {...},
//     "left_leg": {"hip": "LHipJoint", "upper": "LeftUpLeg", "lower": "LeftLeg",
//                  "foot": "LeftFoot", "toe": "LeftToeBase"},          // hip, toe optional
//     "right_leg": {...}
//   }
// A limb may also be an array in chain order: an arm [upper, lower, hand] or
// [clavicle, upper, lower, hand]; a leg [upper, lower, foot] or [hip, upper, lower, foot, toe].
// null for a limb, or for the neck, marks a part the body lacks (a bust's legs): it gets no
// sweep and follows the model's skinning (as deform::detect_rig_map leaves a part not found).
// The loaded map's convention is "json". It must pass deform::validate_rig_map.
#pragma once

#include <filesystem>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::io {

// Reads the override for `skeleton`. Throws LoadError naming the file and the problem: not
// JSON, a missing or unknown part or role, a joint name the skeleton lacks, or chains that do
// not follow the hierarchy.
deform::RigMap load_rig_map_json(const std::filesystem::path& path,
                                 const deform::Skeleton& skeleton);

// Writes `map` in the format above, limbs as keyed objects. Throws std::invalid_argument when
// the map does not fit `skeleton` (validate_rig_map) and std::runtime_error naming the file
// when it cannot be written.
void save_rig_map_json(const deform::RigMap& map, const deform::Skeleton& skeleton,
                       const std::filesystem::path& path);

}  // namespace sweepd::io
