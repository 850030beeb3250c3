// Body samples: a few thousand of a rest mesh's vertices that outline every part of the body,
// skinned cheaply on any pose (motion/body_floor.h lifts the body by them,
// motion/body_contacts.h finds the parts resting on the floor by them).
//
// Per joint (each vertex's strongest influence), the vertices furthest along 64 directions
// spread over the sphere: the lowest point of a part turned any way lies within about 2.5 % of
// its radius above the lowest sample. The skin blended across a joint and its parent is sampled
// the same way again, in six bands by the joint's share: bent, its lowest point is where the
// two bones' skins meet (a kneeling knee's front), which at rest is no part's furthest point
// (the heavy female knocked down forwards: a thigh vertex near the knee 2.5 cm below every
// sample; -0.92 cm with three bands, -0.49 with six). Each
// sample is skinned by linear blending with its own weights (position, height).
// swept_height: where the sweep puts a sample's skin, roughly: the sweep keeps a bent joint's
// volume where linear blending draws the skin in towards the joint (a bent elbow on the floor
// lay 1.8 cm below its linearly blended samples). Where a sample's two strongest influences
// are a joint and its parent, the blended sample moved out from that joint to the weighted
// mean of its distances from it under each influence alone (the same at a straight joint or
// with one influence), then across the outside of the bend as a tube bent at a mitre is: by
// 1 / cos(bend / 2) (at most 2x, a 120° bend) along the bend's outer bisector, nothing on the
// inside. Kneeling knees knocked down forwards lay 1.5-4.2 cm below their samples moved out
// only (the sweep's knee skin 1.1-1.4x its rest distance from the joint at a 100° bend).
// Before the mitre, a sample within a link key's span of that joint (its rest distance along
// its own bone over the span from the joint key to the link key: half the bone with one link
// key per link, the binding's default) is turned from its bone's frame towards the other
// bone's as the sweep's keys turn it, half-way at the joint, none at the link key (easing in as
// the square of what is left of that span, as the keys' B-spline basis does), where that
// is further than its linear blend turns it (its distance from the joint kept): with one link
// key, the heavy female knocked down forwards laid a thigh vertex 1.6 cm above her knee bent
// 66° (knee weight 0.017) 2.5 cm below its linear blend, turned about 28° with the shin, and
// went 1.20 cm below the floor; 0.00 now.
// Not where an influence is in `linear`: the feet, whose soles foot
// planting puts on the floor by linear blending (moved out, a kneeling leg's stretched ankle
// lifted the body 0.6-1.4 cm off its knee).
// Inputs:  model (rest mesh, skin weights, skeleton), linear (per joint, or empty).
// Outputs: vertex (the samples, sorted, no repeats), joint (each one's strongest influence);
//          position() / height() / swept_height() of sample i under skinning matrices (world *
//          rest inverse per joint, deform::skinning_matrices).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::motion {

class BodySamples {
 public:
  explicit BodySamples(const deform::Model& model, const std::vector<bool>& linear = {});

  std::size_t size() const { return vertex_.size(); }
  std::uint32_t vertex(std::size_t i) const { return vertex_[i]; }
  int joint(std::size_t i) const { return joint_[i]; }
  const glm::vec3& rest(std::size_t i) const { return rest_[i]; }
  // Its skin: influences (joint indices) and their weights.
  const std::array<std::uint16_t, deform::kInfluences>& skin_joints(std::size_t i) const {
    return skin_joints_[i];
  }
  const std::array<float, deform::kInfluences>& skin_weights(std::size_t i) const {
    return skin_weights_[i];
  }
  glm::vec3 position(std::size_t i, std::span<const glm::mat4> skinning) const;
  float height(std::size_t i, std::span<const glm::mat4> skinning) const;
  float swept_height(std::size_t i, std::span<const glm::mat4> skinning) const;

 private:
  // Per sample: its rest position, strongest joint and skin (copied: the samples outlive the
  // model they were made from, in a Retargeter).
  std::vector<std::uint32_t> vertex_;
  std::vector<glm::vec3> rest_;
  std::vector<int> joint_;
  std::vector<std::array<std::uint16_t, deform::kInfluences>> skin_joints_;
  std::vector<std::array<float, deform::kInfluences>> skin_weights_;
  // Per sample: the joint its skin bends about (or -1), that joint's rest position, its parent
  // and the rest direction of the bone from that parent to it.
  std::vector<int> bend_joint_;
  std::vector<glm::vec3> bend_rest_;
  std::vector<int> bend_parent_;
  std::vector<glm::vec3> bend_bone_;
  // Per sample: how far the sweep turns it towards the bone across its bend joint, beyond its
  // linear blend (0: not), and whether it lies on the parent's side of that joint.
  std::vector<float> sweep_turn_;
  std::vector<bool> sweep_turn_parent_side_;
};

}  // namespace sweepd::motion
