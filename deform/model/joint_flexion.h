// joint_flexion: pose a limb by its anatomical angle. The flexion of a joint is the angle
// between its two links — upper (parent joint → joint) and lower (joint → its first child) —
// measured about a world axis; 0 for a straight limb. A rest pose may already be bent (the
// shared male's elbows are flexed 46° at rest, its knees 6°), so "an elbow bent 150°" is a
// flexion of 150°, a turn of 104° from that rest pose; a turn of 150° would fold the forearm
// 196°, through the upper arm.
// Inputs:  skeleton, the joint's index (it needs a parent and a child), a world axis (any
//          length but zero), an angle in degrees.
#pragma once

#include <glm/glm.hpp>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"

namespace sweepd::deform {

// The joint's flexion at rest, in degrees, signed by the right-hand rule about `world_axis`.
float rest_flexion_degrees(const Skeleton& skeleton, int joint, glm::vec3 world_axis);

// Sets the joint's local rotation in `pose` to its rest rotation turned about `world_axis` so
// that the limb is flexed to `degrees` (the joint's ancestors are assumed at rest). Throws
// std::invalid_argument naming the joint when it has no parent or no child.
void flex_joint(const Skeleton& skeleton, Pose& pose, int joint, glm::vec3 world_axis,
                float degrees);

// Sets the joint's local rotation in `pose` to its rest rotation turned `degrees` about
// `world_axis` (the turn expressed in the parent's rest frame, so the joint's ancestors are
// assumed at rest; a root turns about the world axis itself). Any joint; no flexion measured.
void turn_joint(const Skeleton& skeleton, Pose& pose, int joint, glm::vec3 world_axis,
                float degrees);

}  // namespace sweepd::deform
