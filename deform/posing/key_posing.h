// pose_key_ellipses: where a sweep's key ellipses go in a pose (paper §4.1).
//
// A joint key keeps its place relative to its joint (its centre stays at the joint, or at the
// section centroid attached to it) and turns by the rotation halfway (slerp 0.5) between the
// world rotations of the joint's upper link (its parent joint) and its lower link (the joint),
// so a bend or a twist is shared between the two sides of the joint. The torso's first key (at
// the hips) has no upper link on the body and turns with the hips: a root joint above them
// (Mixamo-to-Unity's and Unreal's "Root"), which the clips leave at rest while the hips take the
// body's heading, turned it through half that heading against the chest (the corpus child
// turned about, cmu_01_01 frame 1200: a band round the waist 3.13x its rest length, LBS 0.89x
// there; now 1.55x at that frame's worst edge). A link key follows its
// link rigidly, except on the neck and the torso: there a link key turns by the slerp, at its
// fraction along the link, between the turns of the joint keys at the link's two ends. The
// rig's two or three neck joints stand for seven vertebrae that share a head turn, so the twist
// spreads along the neck instead of stepping at each joint (the CMU clips put 66° of an 88°
// head turn on Neck1, which twisted the throat through 66° within 3.5 cm around that joint).
// The torso's three or four spine joints stand for seventeen vertebrae: a spine joint sits
// near the back (the shared male's LowerBack 16 cm behind the belly), so its 30° forward bend
// in cmu_01_01 (frames 197, 1257) turned the keys on either side of it 15° apart, 3-4 cm apart
// on the spine, so their planes crossed inside the belly, which folded through itself in a dark
// band across the waist (docs/contact_sheet.png). Spread, the torso's worst edge over cmu_01_03
// fell 2.99 -> 2.88x (male) and 2.79 -> 2.43x (20k mannequin). Spreading alone does not undo
// the fold where the rest planes already crowd the belly (the male's torso crease with the
// spine bent 30°: 179.9° -> 169.4°); with the torso's rest planes turning gradually too
// (deform/binding/chain_key_ellipses.h) it was 80.9°. The torso's key centres are then laid
// along its own centre line rather than carried round the joints: from the first key, each
// next key sits its rest spacing further on, turned halfway between the two keys' turns, and
// the gap this leaves at the last key (which its joint carries, so the shoulders and neck stay
// on the chest) is shared out along the chain by rest length. Carried round a joint 6 cm
// behind it, a key beside the bent joint swung towards its neighbour (3.1 -> 1.7 cm apart at a
// 45° bend), their planes crossed 9 cm in front, inside the belly, and a crease line stayed
// (80.9° at 30°, 148.6° at 45°); laid along the centre line 21.1° and 41.1°
// (tests/deform/posing/spine_bend_test.cpp).
// The neck's link keys keep their centres on their links.
// An inner joint key (elbow, knee, spine and neck joints: both links on the sweep) then lies
// in the plane halfway between two links bent by φ, which cuts a tube in an ellipse stretched
// by 1/cos(φ/2) along the bend (a mitre). Its ellipse reaches as far as that plane's on the
// outside of the bend (each half-axis by how much it points along the bend) and keeps its
// inner side: the half-axes grow by half the stretch and the ellipse's centre (its in-plane
// offset, KeyEllipse::offset) moves out by the other half. With the rest half-axes the sweep
// pinches the joint (the shared male's elbow turned 135° kept 26 cm² of its section near the
// joint, LBS 36); stretched both ways, its inner side passes the bend's centre into the
// sweep's fold, which the integral counts negatively and the mesh hardly resolves (the arm
// region 8.9 points above the integral at a 150° elbow, so volume correction overshot).
// φ is the swing between the links (the angle between the key normal as each link carries
// it), so twist alone stretches nothing; the stretch is capped at kLargestMitreStretch (a 133°
// swing), past which the two links' sections overlap and the mitre grows without bound. Only
// a joint bent further than at rest is mitred: the rest key already has the section of a
// joint the rest pose bends (the male's elbows, 46°), and straightening it inflated the arm.
// The growth goes into the joint key's control value of a(t), b(t) and o(t) (Sweep's quadratic
// B-splines through the keys' values): the keys beside it change by that control's basis
// function, so a(t), b(t) and o(t) change only up to halfway to the keys two away. (A change of the
// joint key's value alone would ripple along the whole limb: 2.7 mm at the hand for a 135°
// elbow.) The first joint key (shoulder, hip, neck base) keeps its half-axes: the link before
// it is not on the sweep. How the growth spreads depends only on the rest keys: mitre_spread
// computes it once per sweep, so posing allocates nothing.
// Inputs:  sweep (rest keys and anchors), spread: mitre_spread(sweep), skeleton (parents),
//          joint_rotation: J world rotation
//          deltas (pose · rest⁻¹), rest_joint / pose_joint: J world joint positions.
// Output:  keys: sweep.rest_keys.size() posed key ellipses.
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

// Per key k: how a change of key k's control value shows at keys k-1, k, k+1, relative to k.
std::vector<std::array<float, 3>> mitre_spread(const BoundSweep& sweep);

void pose_key_ellipses(const BoundSweep& sweep, std::span<const std::array<float, 3>> spread,
                       const Skeleton& skeleton, std::span<const glm::quat> joint_rotation,
                       std::span<const glm::vec3> rest_joint, std::span<const glm::vec3> pose_joint,
                       std::span<KeyEllipse> keys);

// The halfway rotation between a and b along the shorter arc.
glm::quat halfway(const glm::quat& a, const glm::quat& b);

inline constexpr float kLargestMitreStretch = 2.5f;
// 1/cos(φ/2) for the angle φ between two unit key normals, at most kLargestMitreStretch.
float mitre_stretch(const glm::vec3& upper_normal, const glm::vec3& lower_normal);

}  // namespace sweepd::deform
