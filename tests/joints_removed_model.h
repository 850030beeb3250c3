// A model with some joints dropped, as a simpler rig of the same body would have them: each
// removed joint's children hang from its parent (their rest transforms composed with its, so
// nothing moves at rest) and its skin weights are merged into its parent's. For tests that check
// nothing depends on a rig having every joint: a spine joint, a clavicle, the toes, a neck joint.
// Input: a Model (by value), the joints to remove (none of them a root; uniform scales, as every
// shared body has). Output: the Model without them, joint indices renumbered parents-first.
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model without_joint(deform::Model model, int removed) {
  std::vector<deform::Joint>& joints = model.skeleton.joints;
  const deform::Joint gone = joints.at(removed);
  if (gone.parent < 0) throw std::invalid_argument("without_joint: " + gone.name + " is a root");
  for (deform::Joint& joint : joints) {
    if (joint.parent == removed) {
      joint.rest_translation =
          gone.rest_translation + gone.rest_rotation * (gone.rest_scale * joint.rest_translation);
      joint.rest_rotation = gone.rest_rotation * joint.rest_rotation;
      joint.rest_scale *= gone.rest_scale;
      joint.parent = gone.parent;
    }
    if (joint.parent > removed) --joint.parent;
  }
  joints.erase(joints.begin() + removed);
  for (std::size_t v = 0; v < model.skin_joints.size(); ++v) {
    std::array<std::uint16_t, deform::kInfluences>& slot = model.skin_joints[v];
    std::array<float, deform::kInfluences>& weight = model.skin_weights[v];
    for (int k = 0; k < deform::kInfluences; ++k) {
      if (slot[k] == removed)
        slot[k] = static_cast<std::uint16_t>(gone.parent);
      else if (slot[k] > removed)
        --slot[k];
    }
    // Two slots on the parent now: one keeps the sum, the other none.
    for (int a = 0; a < deform::kInfluences; ++a)
      for (int b = a + 1; b < deform::kInfluences; ++b)
        if (slot[a] == slot[b] && weight[b] > 0.0f) weight[a] += weight[b], weight[b] = 0.0f;
  }
  return model;
}

// The joints removed, deepest first (each merged into its parent, which may be removed after).
inline deform::Model without_joints(deform::Model model, std::vector<int> removed) {
  std::sort(removed.begin(), removed.end(), std::greater<int>());
  removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
  for (int j : removed) model = without_joint(std::move(model), j);
  return model;
}

// The joints and every joint below them (the toes with their tips).
inline std::vector<int> with_descendants(const deform::Skeleton& skeleton,
                                         const std::vector<int>& joints) {
  std::vector<bool> below(skeleton.size(), false);
  for (int j : joints) below.at(j) = true;
  std::vector<int> all;
  for (int j = 0; j < skeleton.size(); ++j) {
    const int parent = skeleton.joints[j].parent;
    if (parent >= 0 && below[parent]) below[j] = true;
    if (below[j]) all.push_back(j);
  }
  return all;
}

}  // namespace sweepd::test_models
