// skinned_share_influences: the skin influences that each vertex's skinned share follows (the
// part the sweeps leave to the model's own skinning, VertexBinding::skin_weight).
//
// The model's painted weights, except where an arm sweep meets the torso: on the vertices bound
// to an arm sweep and to the torso sweep that also have a skinned share (the ring around the
// arm's root: armpit, shoulder, shoulder blade) the weights are smoothed over the mesh once, at
// bind time. Painted weights jump there: on the shared male the spine's weight goes 0.12 -> 0.33
// across one 9 mm armpit edge (0.10 apart after smoothing), and with the arm raised LBS tears
// that edge 5.6x. About a third of the armpit is skinned after blending (the shoulder's skinned
// share spreads around the arm's root with the share smoothing), so the edge stretched 3.5x
// with sweeps in cmu_01_03; 2.86x now. Each pass replaces a ring vertex's weights by half its
// own plus half its neighbours' mean, each neighbour weighted by 1 / edge length (as the shares
// are smoothed); vertices outside the ring keep their painted weights and hold the ring's
// border. kShoulderSkinSmoothingPasses: more passes lower the armpit further (2.64x at 20) but
// move the skinned share of the ring's lower edge, behind the armpit, towards the arm, where
// the shares' own gradient already stretches an edge 2.96x (3.00x at 10 passes, 2.99x at 8).
// The largest kInfluences weights are kept and scaled to sum to 1. LBS and DQS keep the model's
// own weights.
// Inputs:  model (n vertices), mesh (the model welded: weld_mesh; the passes walk its
//          adjacency), bindings (n, with shares: blend_shares), sweeps (their parts).
// Output:  joints and weights, n each; equal to the model's outside the ring.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"
#include "deform/mesh/welded_mesh.h"

namespace sweepd::deform {

inline constexpr int kShoulderSkinSmoothingPasses = 8;

struct SkinInfluences {
  std::vector<std::array<std::uint16_t, kInfluences>> joints;
  std::vector<std::array<float, kInfluences>> weights;
};

SkinInfluences skinned_share_influences(const Model& model, const WeldedMesh& mesh,
                                        std::span<const VertexBinding> bindings,
                                        std::span<const BoundSweep> sweeps);

}  // namespace sweepd::deform
