// Pose: what a client sends to deform a model — one local rotation per joint plus the
// translation of the root.
//
//   local_rotations   skeleton.size() unit quaternions (w, x, y, z), in the skeleton's joint
//                     order. Each REPLACES that joint's rest local rotation (glTF animation
//                     semantics): the identity means "no rotation relative to the parent",
//                     not "keep the rest pose". rest_pose() gives the rest rotations.
//   root_translation  replaces the rest local translation of joint 0 (always a root, since
//                     joints are stored parents first). Any further roots (parent -1) are
//                     shifted by the same amount, root_translation - joint 0's rest
//                     translation, so a rig split into several trees moves as one.
// Rest translations and scales of all other joints are kept.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <string>
#include <vector>

#include "deform/model/skeleton.h"

namespace sweepd::deform {

struct Pose {
  std::vector<glm::quat> local_rotations;
  glm::vec3 root_translation{0.0f};
};

// The pose that reproduces the rest skeleton: every joint's rest rotation, joint 0's rest
// translation (zero translation for an empty skeleton).
Pose rest_pose(const Skeleton& skeleton);

// Checks a pose against the skeleton once, before it is used. Returns "" when it fits;
// otherwise the first problem in words, naming the joint by index and name: a rotation count
// that differs from the joint count, a NaN or infinite component, a zero-length (or
// denormal-length) quaternion, a quaternion whose length differs from 1 by more than
// `length_tolerance` (default: none is too long or short), or a non-finite root translation.
// Fixes what it can in place: non-unit quaternions within the tolerance are normalised.
std::string normalize_and_validate(
    Pose& pose, const Skeleton& skeleton,
    double length_tolerance = std::numeric_limits<double>::infinity());

}  // namespace sweepd::deform
