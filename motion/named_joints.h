// Named joints: rotations keyed by joint name (sweepd's PoseByName), mapped onto a model's
// skeleton once, in the library, so no client carries a rig-naming table.
//
// named_joints(skeleton, model_rig, names): the model joint each name drives, in order:
//   1. a model joint with exactly that name;
//   2. the role the names' naming convention gives it (deform::match_name_roles: mixamo, CMU,
//      Unreal, Rigify, SMPL, VRM, ...; pelvis, head, clavicles, limb joints, hip links, toes),
//      on the model joint of that role in `model_rig` (deform::rig_roles).
//   Inputs: skeleton (joint count J), model_rig (its RigMap, e.g. BoundModel::rig), names (N).
//   Output: N model joint indices in [0, J).
//   Throws std::invalid_argument naming every name that matches neither way (and the model's
//   joints), or two names that land on one model joint. Names are one per joint: of two that
//   read the same once case and prefixes are dropped ("LeftArm", "mixamorig:LeftArm"), only the
//   first gets the role, so the second is reported unknown unless it is a model joint's name.
// pose_from_named_rotations(skeleton, joints, rotations, root_translation): the model's
//   deform::Pose with its rest rotations, each joints[i] replaced by rotations[i] (N each).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::motion {

std::vector<int> named_joints(const deform::Skeleton& skeleton, const deform::RigMap& model_rig,
                              std::span<const std::string> names);

deform::Pose pose_from_named_rotations(const deform::Skeleton& skeleton,
                                       std::span<const int> joints,
                                       std::span<const glm::quat> rotations,
                                       const glm::vec3& root_translation);

}  // namespace sweepd::motion
