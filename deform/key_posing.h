// pose_key_ellipses: where a sweep's key ellipses go in a pose (paper §4.1).
//
// A joint key keeps its place relative to its joint (its centre stays at the joint, or at the
// section centroid attached to it) and turns by the rotation halfway (slerp 0.5) between the
// world rotations of the joint's upper link (its parent joint) and its lower link (the joint),
// so a bend or a twist is shared between the two sides of the joint. A link key follows its
// link rigidly, except on the neck: there a link key's centre follows its link, but it turns
// by the slerp, at its fraction along the link, between the turns of the joint keys at the
// link's two ends. The rig's two or three neck joints stand for seven vertebrae that share a
// head turn, so the twist spreads along the neck instead of stepping at each joint (the CMU
// clips put 66° of an 88° head turn on Neck1, which twisted the throat through 66° within
// 3.5 cm around that joint).
// Inputs:  sweep (rest keys and anchors), skeleton (parents), joint_rotation: J world rotation
//          deltas (pose · rest⁻¹), rest_joint / pose_joint: J world joint positions.
// Output:  keys: sweep.rest_keys.size() posed key ellipses (half-axes copied from rest).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>

#include "deform/bound_model.h"

namespace sweepd::deform {

void pose_key_ellipses(const BoundSweep& sweep, const Skeleton& skeleton,
                       std::span<const glm::quat> joint_rotation,
                       std::span<const glm::vec3> rest_joint, std::span<const glm::vec3> pose_joint,
                       std::span<KeyEllipse> keys);

// The halfway rotation between a and b along the shorter arc.
glm::quat halfway(const glm::quat& a, const glm::quat& b);

}  // namespace sweepd::deform
