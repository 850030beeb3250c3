// Two-bone IK: the end of a limb (an ankle, a wrist) moved to a target by turning the limb's
// upper and middle joints, its root joint (hip, shoulder) staying where it is. Shared by foot
// planting (motion/foot_planting.h: ankles) and body contacts (motion/body_contacts.h: wrists).
//
// move_limb_end
//   Inputs:  skeleton; the limb's joints (upper: hip or shoulder, lower: knee or elbow, end:
//            ankle or wrist, each a descendant of the one before); shift, the end joint's move
//            (world, m); world (forward_kinematics of pose), rotation (world_rotations of pose);
//            bend_if_straight, a direction the middle joint bends the lower bone towards where
//            the limb is straight (zero: a straight limb is left as it is), and towards which
//            a nearly straight limb's bend plane is eased (below); softness, the soft
//            reach's width as a fraction of the limb's length (0: a hard limit; kSoftReach).
//   Output:  pose's local rotations of upper, lower and end: the end joint moves towards its
//            target (where it is, plus shift), along the direction from the root, all the way
//            where the target lies within the limb's length less the softness, and beyond that
//            as far as the soft reach allows (soft IK: the limb straightens smoothly as the
//            target goes out of reach instead of snapping its middle joint; with no softness it
//            stops at the limb's length); the limb bends in its own plane, the upper bone
//            swings, and the end keeps its world rotation. Joints between these follow their
//            parents. A limb bent less than kPlaneFromPoseBend bends in its own plane eased
//            towards bend_if_straight's (all the way at straight): the pose hardly defines the
//            plane of a nearly straight limb, and a clip's noise turns it from frame to frame.
// move_limb_middle
//   Inputs:  as move_limb_end's; shift (world, m; its vertical part unused).
//   Output:  pose's local rotations of upper, lower and end: the upper bone swings about its
//            root so that the middle joint (knee, elbow) moves across by the shift, keeping its
//            height as far as the bone reaches; the lower bone keeps its world rotation (what
//            hangs below it moves across with the middle joint) unless the middle joint would
//            then fold past its bend before the swing (the clip's): the lower bone then turns
//            about the middle joint towards the upper bone by the excess, and the end keeps its
//            world rotation.
// world_rotations: each joint's world rotation under a pose (size skeleton.size()).
#pragma once

#include <vector>

#include "deform/model/pose.h"
#include "deform/model/skeleton.h"

namespace sweepd::motion {

// The soft reach's width, a fraction of the limb's length (thigh and shin): within the length
// less this, an end reaches its target exactly; beyond, its reach approaches the full length
// exponentially over this width. At 1 % a leg with equal bones is bent 16° where soft IK takes
// over (its knee then moves about 3.5 times as far as its ankle's distance from the hip changes;
// 2° from straight, about 30 times).
inline constexpr float kSoftReach = 0.01f;

// Degrees: below this bend, a limb's own bend plane (the cross product of its bones, whose
// length is the bend's sine) is eased towards bend_if_straight's by adding that plane's normal
// times the sine's shortfall, so that the plane turns smoothly with the pose. CMU's knees stand
// within 0-5° of straight, or overextended, on planted frames (cmu_01_03 frames 3384-3392), and
// their plane turned by tens of degrees a frame: the RiggedFigure's knee, bent 38° by the IK,
// swung sideways 5.5-6.6 cm in a frame. At 20° the plane of a knee the clip bends as a walk
// does (20-40° in stance) is its own, or nearly.
inline constexpr float kPlaneFromPoseBend = 20.0f;

struct LimbJoints {
  int upper = -1, lower = -1, end = -1;
};

void move_limb_end(const deform::Skeleton& skeleton, LimbJoints limb, glm::vec3 shift,
                   const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                   glm::vec3 bend_if_straight, float softness, deform::Pose& pose);

void move_limb_middle(const deform::Skeleton& skeleton, LimbJoints limb, glm::vec3 shift,
                      const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                      deform::Pose& pose);

std::vector<glm::quat> world_rotations(const deform::Skeleton& skeleton, const deform::Pose& pose);

}  // namespace sweepd::motion
