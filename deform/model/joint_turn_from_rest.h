// joint_turn_from_rest: how far a joint has turned from its rest pose, as one angle — the angle of
// the rotation between its upper link (the parent joint) and its lower link (the joint itself),
// i.e. of conj(R_parent) · R_joint with R the world rotation deltas (pose · rest⁻¹).
// Bends and twists both count; a root joint (no parent) measures against the identity.
// Inputs:  skeleton (parents), joint_rotation: J world rotation deltas, joint: its index.
// Output:  the angle in radians, in [0, π].
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>

#include "deform/model/skeleton.h"

namespace sweepd::deform {

float joint_turn_from_rest(const Skeleton& skeleton, std::span<const glm::quat> joint_rotation,
                           int joint);

}  // namespace sweepd::deform
