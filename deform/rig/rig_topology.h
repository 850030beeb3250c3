// Rig topology: finds a RigMap from the hierarchy and rest-pose geometry alone, for skeletons
// whose joint names say nothing (e.g. "joint_12").
//
// Input: a skeleton whose world rest pose is a standing human, or its upper body, in any
// orientation (Y or Z up) and roughly an A- or T-pose. Output: the map, convention
// "topological", with each part's finding kByShape, or kAbsent with the reason in its note
// (legs, one arm, ...). Throws std::invalid_argument, saying where the search stopped, only
// when it finds no joint where limbs branch or cannot tell which way is up.
//
// How: the first joint below the root with three or more child chains is the pelvis when its
// biggest child chain (the spine) branches again (at the chest: three ways, or two for a body
// without a head, whose head is then absent) and its two other chains (the legs) both point
// within 60° of straight away from the spine (the legs, the two furthest-reaching); otherwise it is
// the chest of a legless body whose torso runs up to it from the root. "Up" points from pelvis to
// chest; the neck is the chest's child chain pointing most upward, the arms the two others
// reaching furthest. Along each limb the two consecutive segments with the largest summed
// length are upper arm + forearm (thigh + shin); the joint before them, if any, is the
// clavicle (hip link), the joint after them the hand (foot) and, for legs, the next one the
// toe. The head is the first neck joint that branches or ends. Left is up x forward, forward
// taken from the feet (ankle to toe) when toes are present, otherwise the glTF convention (+Z
// when Y is up, -Y when Z is up); a lone arm or leg is on the side it lies from the torso.
// Beyond that:
// - a skeleton of several roots (glTF joints whose common parent node is not a joint, as
//   OpenPose's MidHip, LHip and RHip) is searched as if one node at its largest root held them;
// - a one-joint torso: where the legs, arms and neck all branch from one joint (low-poly game
//   rigs: the two children reaching furthest in agreeing directions are the legs), where the
//   spine ends where the legs start (OpenPose), or a bust whose arms and neck hang from the root,
//   the torso chain is that one joint and up points from it to the mean of the joints above it;
// - an arm of three joints whose first sits on the torso's centre line (OpenPose's LShoulder
//   at the neck) is clavicle, upper arm and a forearm without a hand joint (hand -1).
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <span>

#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform {

RigMap detect_rig_map_by_topology(const Skeleton& skeleton);

// Where the feet point (ankle to toe, made level with `up`), summed over both legs: the body's
// forward whatever its joints are named. nullopt where a leg has no toe or the feet do not agree
// on a mostly level direction. joint_positions: world rest position per joint.
std::optional<glm::vec3> toes_forward(std::span<const glm::vec3> joint_positions,
                                      const glm::vec3& up, const LegJoints& a, const LegJoints& b);

}  // namespace sweepd::deform
