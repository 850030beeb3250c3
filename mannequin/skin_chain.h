// SkinChain: smooth skin weights along a chain of bone segments (spine, a leg, an arm).
//
// Each bone is a segment skinned to one joint. A point takes the joint of its nearest segment;
// around each junction of two consecutive segments the two joints blend smoothly (smoothstep)
// across a zone of +-blend_half_width measured across the plane that bisects the two segment
// directions, so the weights are continuous where the nearest segment changes.
//
// Inputs:  chain  bones in order from the chain's root outwards; p  a rest-pose position
// Outputs: up to three (joint, weight) pairs with weights >= 0 summing to 1
#pragma once

#include <array>
#include <glm/glm.hpp>
#include <vector>

namespace sweepd::mannequin {

struct SkinBone {
  int joint = 0;  // skeleton joint the segment's skin follows
  glm::vec3 start{0.0f};
  glm::vec3 end{0.0f};
  float blend_half_width = 0.0f;  // half-width of the blend zone at `start` (ignored for the first)
};

struct SkinChain {
  std::vector<SkinBone> bones;  // consecutive: bones[i].start == bones[i - 1].end
};

struct JointWeight {
  int joint = 0;
  float weight = 0.0f;
};

// Writes the weights of p into `weights` and returns how many (1 to 3) it wrote.
int chain_skin_weights(const SkinChain& chain, const glm::vec3& p,
                       std::array<JointWeight, 3>& weights);

}  // namespace sweepd::mannequin
