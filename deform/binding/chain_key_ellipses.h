// fit_chain_key_ellipses: the rest key ellipses of one control sweep along a joint chain (paper
// §3.2).
//
// One joint key per chain joint, fitted to the cross-section cut by a plane through the joint
// orthogonal to its lower link (the last joint uses the link above it), centred at the joint or
// at the section's centroid (JointKeyCentre) — a joint-centred key's ellipse is still the
// section's (fitted about its centroid), placed by the key's in-plane offset from the joint
// (KeyEllipse::offset); and
// `intermediate_keys_per_link` link keys evenly along each link, centred at their section's
// centroid. Each section keeps only the loop around the link (cross_section) and is fitted by
// its area moments with the area matched (fit_polygon_ellipse).
// On the torso the planes turn gradually instead (beyond the paper): a joint key's plane is
// orthogonal to the bisector of its two links, a link key's to the mix of its link's two end
// joints' normals at its fraction. A spine bends at its joints, and the spine joints sit near
// the back: the shared male's links lean 20° apart at LowerBack, 16 cm behind the belly, so
// the planes of the keys 3 cm either side of it, orthogonal to their own links, crossed inside
// the belly, whose front rows then spanned a fifth of the torso's parameter in 3 cm of skin;
// a forward bend of the spine folded it through itself (cmu_01_01 frames 197 and 1257, torso
// crease at keys 179°; 58° and 72° now). Limbs keep the paper's rule: their joint keys'
// mitres (deform/posing/key_posing.h) are measured against it.
// A joint key whose cut is unusable — no closed loop, or a loop that takes in the neighbouring
// body (a shoulder plane cutting the torso: area over kMaxJointKeyAreaRatio times the nearest
// link key's) — copies the half-axes of the nearest usable key and is marked as a fallback.
// The first axis of every key is chosen among the fitted major/minor axes to stay closest to the
// previous key's (to x_hint for the first key), so Q(t) does not twist by 90° where a limb's
// section turns from wide to deep; a may therefore be smaller than b.
// A chain whose last joint's bone carries an end of the body (no hand or head joint: OpenPose's
// forearm and neck bones; carried_end.h) runs on to that end: link keys along the bone from the
// joint to `end`, and a last key at `end` (fraction 1 on the joint's own bone), all riding the
// chain's last joint; that joint's key plane is then orthogonal to the bone, from joint to end.
// Inputs:  positions, indices: the rest mesh with UV-seam duplicates welded (cut loops are
//          chained through shared vertices), world_rest (Skeleton::world_rest_matrices, one per
//          joint), part and chain (root first), end (the carried end's rest point, or none;
//          chain and end give at least two points), options, x_hint (world direction).
// Output:  BoundSweep with chain, anchors, rest_keys, key_fit_errors, key_area_ratios,
//          key_fallback filled (rest_volume is left to the caller).
// Throws std::invalid_argument naming the part when no key of the chain can be fitted or two
// chain joints coincide.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

inline constexpr float kMaxJointKeyAreaRatio = 1.8f;

BoundSweep fit_chain_key_ellipses(std::span<const glm::vec3> positions,
                                  std::span<const std::uint32_t> indices,
                                  std::span<const glm::mat4> world_rest, BodyPart part,
                                  std::span<const int> chain, std::optional<glm::vec3> end,
                                  const BindOptions& options, glm::vec3 x_hint);

}  // namespace sweepd::deform
