// Segmentation and blending (paper §3.5): how much of each vertex follows which sweep, and how
// much follows the model's own skinning.
//
// Every sweep but the torso's hangs off the torso at its first joint (shoulder, hip, neck base).
// Across that joint a transition region is bounded by two planes orthogonal to the sweep's first
// link, transition_half_width × the link's length on either side; a vertex's share of the limb
// sweep rises smoothly (smoothstep) from 0 at the inner plane to 1 at the outer one, times a mask
// from the model's skin weights on that limb (so the chest beside a shoulder stays torso), and
// the torso takes the rest. A vertex keeps its three largest sweep shares.
// At a sweep's far end (wrist, ankle, head) the share of the skinned remainder rises the same
// way across two planes around the end joint, or with the skin weight of the hand/foot (from
// 0 at one half to 1), whichever is larger. A leg's two planes end at the ankle: beyond its
// last key the sweep only extrapolates, and a foot pointed 45° (the range of motion's plantar
// flexion) stretched the heel 2.05x where skinning stretches it 1.60x (the shared male); its
// feet are now skinning's on every corpus body. An arm's planes straddle the wrist, since the
// forearm's twist is spread by the sweep up to the hand (the candy wrapper: moved, a 150°
// twist kept 66 % of a forearm section instead of 80 %). The head's painted weights reach far down the
// throat, so the neck's hand-over instead rises linearly with the distance along the surface
// from where the head's skin weight passes one half, reaching 1 one neck length further (the neck
// chain's joint-to-joint length). Beyond the torso's first and last keys (below the pelvis,
// above the chest: the shoulders) its share hands over to skinning the same way as the limbs',
// starting at the key. A sweep that runs on to the end its last bone carries (a forearm bone
// that carries the hand, a neck bone the head: BoundSweep::rest_path) hands over by the planes
// around that end alone: the end's skin weight is the bone's, all along the part.
// Where sweeps meet, the shares are smoothed over the mesh, and around the hips and the armpits
// a little beyond (sweep_blending.cpp: kShareSmoothingReach, kArmShareSmoothingReach), so that
// no share steps across one edge at the border of the meeting.
// Last, no skinned share rises faster along the surface than from 0 to 1 over a twentieth of
// the longest sweep's chain: a steeper hand-over spreads back over the swept skin, since an edge
// across it stretches by the share's step times how far apart the sweep and skinning put it.
// Every share is a continuous function of position and skin weights.
// Inputs:  model (n vertices), mesh (the model welded: weld_mesh; the smoothing and the neck's
//          ramp walk its adjacency), rig, world_rest (one per joint), sweeps (part + chain
//          filled), options.
// Output:  n VertexBinding with sweep, weight and skin_weight set (coordinates left empty);
//          the weights and skin_weight sum to 1.
#pragma once

#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/mesh/welded_mesh.h"

namespace sweepd::deform {

std::vector<VertexBinding> blend_shares(const Model& model, const WeldedMesh& mesh,
                                        const RigMap& rig, std::span<const glm::mat4> world_rest,
                                        std::span<const BoundSweep> sweeps,
                                        const BindOptions& options);

// The skinned part at the far end of a sweep's part (kLeftHand for kLeftArm, kHead for kNeck,
// ...), kNone for the torso.
BodyPart end_part(BodyPart sweep_part);

}  // namespace sweepd::deform
